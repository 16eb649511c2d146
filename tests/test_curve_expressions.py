"""Cam profiles written as expressions r(phi) (``lw.curves.polar_expression``): the
reference's third-order jets against closed forms and differences, its expression curve
against differences, the eccentric circular cam written as its polar radius about the
pivot against the ``circle`` curve and the closed form, engine against reference over
whole turns, refusals naming the joint, model files and units.

Tolerances: 1e-10 relative for solves, as in test_cams.py (Newton stops at 1e-12 scaled;
the Jacobians are well conditioned); 1e-12 relative for single jets against their closed
forms (a few roundings of terms of that size); differences as stated where used.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import linkwork as lw
from helpers import eccentric_follower, rel_err, translating_cam, wrap
from linkwork.reference import ReferenceModel
from linkwork.reference import curves as ref_curves
from linkwork.reference.laws import expression, expression3
from test_cams import TOL, compare_with_reference

TAU = 2.0 * math.pi

# a cam profile (m): a rise of 12 mm and a ripple, convex all round (test_cams.profile)
PROFILE = "0.05 + 0.006*(1 - cos(phi)) + 0.002*sin(2*phi)"
# a profile derived from a follower motion law: a cycloidal rise of 10 mm over half a turn
# and the same return (u runs 0 -> 1 -> 0; the cycloid is C2 at both ends of the rise)
CYCLOIDAL = "0.04 + 0.01*(u - sin(2*pi*u)/(2*pi))"
RISE_RETURN = CYCLOIDAL.replace("u", "(1 - abs(phi - pi)/pi)")


# --- the reference's jets, one order further ------------------------------------------------

THIRD = [
    ("0.35 - 0.16*sin(150*t)", lambda t: 0.16 * 150**3 * math.cos(150 * t)),
    ("cos(2*t)", lambda t: 8 * math.sin(2 * t)),
    ("tan(t)", lambda t: 2 * (1 + math.tan(t) ** 2) * (1 + 3 * math.tan(t) ** 2)),
    ("asin(t)", lambda t: (1 + 2 * t * t) / (1 - t * t) ** 2.5),
    ("acos(t)", lambda t: -(1 + 2 * t * t) / (1 - t * t) ** 2.5),
    ("atan(t)", lambda t: (6 * t * t - 2) / (1 + t * t) ** 3),
    (
        "atan2(t, 1 - t)",
        lambda t: -4 / (2 * t * t - 2 * t + 1) ** 2 + 2 * (4 * t - 2) ** 2 / (2 * t * t - 2 * t + 1) ** 3,
    ),
    ("atan2(3*sin(t), 3*cos(t))", lambda t: 0.0),
    ("sinh(t) + cosh(t)", math.exp),
    ("cosh(2*t) - sinh(t)", lambda t: 8 * math.sinh(2 * t) - math.cosh(t)),
    ("tanh(t)", lambda t: -2 * (1 - math.tanh(t) ** 2) * (1 - 3 * math.tanh(t) ** 2)),
    ("exp(-t^2)", lambda t: (12 * t - 8 * t**3) * math.exp(-t * t)),
    ("ln(t) + log(t)", lambda t: 4 / t**3),
    ("log10(t)", lambda t: 2 / (t**3 * math.log(10))),
    ("sqrt(1 + t)", lambda t: 0.375 / (1 + t) ** 2.5),
    ("abs(t - 2) + abs(t)^3", lambda t: 6.0),
    ("min(t^3, 2) + max(t^2, -1)", lambda t: 6.0),
    ("pow(t, 4) - t**2 / 2 + t^-1 + t^2.5", lambda t: 24 * t - 6 / t**4 + 1.875 / math.sqrt(t)),
    ("hypot(t, 1)", lambda t: -3 * t / (1 + t * t) ** 2.5),
    ("hypot(2*sin(t), 2*cos(t))", lambda t: 0.0),
    ("2^t", lambda t: math.log(2) ** 3 * 2**t),
    (
        "t^t",
        lambda t: t**t * ((math.log(t) + 1) ** 3 + 3 * (math.log(t) + 1) / t - 1 / t**2),
    ),
    (
        "1/(2 + sin(t))",
        lambda t: (
            -6 * math.cos(t) ** 3 / (2 + math.sin(t)) ** 4
            - 6 * math.cos(t) * math.sin(t) / (2 + math.sin(t)) ** 3
            + math.cos(t) / (2 + math.sin(t)) ** 2
        ),
    ),
    ("sin(t)*exp(t)", lambda t: 2 * (math.cos(t) - math.sin(t)) * math.exp(t)),
    ("-exp(2*t)", lambda t: -8 * math.exp(2 * t)),
]


@pytest.mark.parametrize("text, closed", THIRD, ids=[t for t, _ in THIRD])
def test_reference_third_derivatives_match_closed_forms_and_differences(text, closed):
    """f''' of every function and operator: the closed form to 1e-12 relative, central
    differences of f'' (h = 1e-6: truncation h^2 f^(5) / 6 and rounding eps f'' / h both
    below 1e-7 of the largest f''' here), and the first three slots are the motion laws'."""
    f3, f = expression3(text), expression(text)
    ts = np.linspace(0.1, 0.9, 17)
    scale = max(0.1, max(abs(closed(t)) for t in ts))
    for t in ts:
        got = f3(float(t))
        assert got[:3] == f(float(t))
        assert abs(got[3] - closed(t)) <= 1e-12 * max(1.0, abs(closed(t))), (t, got[3], closed(t))
        h = 1e-6
        fd = (f3(t + h)[2] - f3(t - h)[2]) / (2 * h)
        assert abs(fd - got[3]) <= 1e-7 * scale, (t, fd, got[3])


def test_reference_third_order_powers_at_zero():
    assert expression3("t^2")(0.0) == (0.0, 0.0, 2.0, 0.0)
    assert expression3("t^3")(0.0) == (0.0, 0.0, 0.0, 6.0)
    assert expression3("t^1 + 1")(0.0) == (1.0, 1.0, 0.0, 0.0)
    # the third derivative alone does not exist: infinite, the motion law's part finite
    assert expression3("abs(t)^2.5")(0.0)[3] == math.inf
    assert expression("abs(t)^2.5")(0.0) == (0.0, 0.0, 0.0)


# --- the reference's expression curve -----------------------------------------------------------


def test_reference_expression_curve_matches_differences_and_repeats():
    """c', c'' from central differences of c and c' (h = 1e-6), c''' from c'' (h = 1e-5:
    error ~1e-9 of |c'''|); c(s + 2 pi) = c(s); the curve is centre + r(phi) e(phi) in the
    world at the start."""
    start = (0.3, -0.1, 0.5)
    curve = ref_curves.build_curve(lw.curves.polar_expression(RISE_RETURN, centre=(0.2, 0.1)), start, "J")
    for s in np.linspace(-7.0, 9.0, 41) + 0.013:
        c = curve(s)
        for k, h in ((1, 1e-6), (2, 1e-6), (3, 1e-5)):
            fd = (curve(s + h)[k - 1] - curve(s - h)[k - 1]) / (2 * h)
            np.testing.assert_allclose(
                fd, c[k], atol=1e-7 * (1 + np.max(np.abs(c[k]))), err_msg=f"c^({k}) at {s}"
            )
        np.testing.assert_allclose(curve(s + TAU)[0], c[0], atol=1e-15)
        phi = s % TAU
        u = 1 - abs(phi - math.pi) / math.pi
        r = 0.04 + 0.01 * (u - math.sin(TAU * u) / TAU)
        world = ref_curves.rot(start[2]) @ c[0] + np.array(start[:2])
        np.testing.assert_allclose(world, [0.2 + r * math.cos(s), 0.1 + r * math.sin(s)], atol=1e-15)


# --- the eccentric circular cam as an expression ---------------------------------------------


def cam(kind: str, curve: dict) -> lw.Mechanism:
    """A cam turning about the origin, from 0.3 rad at 10 rad/s and speeding up at
    5 rad/s^2, under a follower translating along the y axis drawn 3 mm off the profile."""
    return translating_cam(kind, curve, lw.Polynomial([0.3, 10.0, 2.5]))


@pytest.mark.parametrize("kind", ["knife", "roller", "flat"])
def test_the_eccentric_cam_as_an_expression_moves_its_follower_like_the_circle(kind):
    """A circle of radius R whose centre is e from the pivot at angle a on the cam is, as a
    polar profile about the pivot, r(phi) = e cos(phi - a) + sqrt(R^2 - e^2 sin^2(phi - a)).
    The follower then rises by y = e sin(th + a) + sqrt(R'^2 - e^2 cos^2(th + a)), R' = R or
    R + rho (y = e sin(th + a) + R for the flat face); y' and y'' by helpers.eccentric_follower, the
    follower's rate y' thd and acceleration y'' thd^2 + y' thdd. The engine, the reference
    and the circle curve agree with it to 1e-10 over a turn; the reference's s too."""
    e, R, rho, a = 0.02, 0.05, 0.015, 0.7
    text = f"{e}*cos(phi - {a}) + sqrt({R}^2 - {e}^2*sin(phi - {a})^2)"
    circle = lw.curves.circle((e * math.cos(a), e * math.sin(a)), R)
    t = np.linspace(0.0, 0.55, 361)
    th, thd, thdd = 0.3 + 10 * t + 2.5 * t * t, 10 + 5 * t, 5.0
    b = th + a
    y, dy, ddy = eccentric_follower(kind, e, R, rho, b)
    want = (y, dy * thd, ddy * thd**2 + dy * thdd)
    mech = cam(kind, lw.curves.polar_expression(text))
    r = mech.compile().sweep(t)
    by_circle = cam(kind, circle).compile().sweep(t)
    ref = ReferenceModel(mech).sweep(t)
    k = r.columns.index("follower.y")
    for order, (got, c, g_ref) in enumerate(
        zip((r.q, r.qd, r.qdd), (by_circle.q, by_circle.qd, by_circle.qdd), (ref["q"], ref["qd"], ref["qdd"]))
    ):
        assert rel_err(got[:, k], want[order]) <= TOL, order
        assert rel_err(c[:, k], want[order]) <= TOL, order
        assert rel_err(g_ref[:, k], want[order]) <= TOL, order
    s = r.q[:, r.columns.index("F.s")]
    assert np.max(np.abs(wrap(s - ref["q"][:, r.columns.index("F.s")]))) <= TOL


# --- engine against the reference over a turn ------------------------------------------------


def oscillating_roller() -> lw.Mechanism:
    """test_cams.oscillating_roller with its profile written as the expression."""
    m = lw.Mechanism("expression cam, oscillating roller")
    body = m.body("cam", angle=0.2)
    phi0, rho, arm_length = math.radians(40.0), 0.010, 0.070
    r0 = 0.05 + 0.006 * (1 - math.cos(phi0)) + 0.002 * math.sin(2 * phi0)
    b = (r0 + rho) * np.array([math.cos(phi0), math.sin(phi0)])
    o4 = b + arm_length * np.array([-math.sin(phi0), math.cos(phi0)])
    arm = m.link("arm", o4, b)
    m.revolute(m.ground, body, at=(0, 0), name="O")
    m.revolute(m.ground, arm, at=o4, name="O4")
    m.cam_follower(body, arm, b, lw.curves.polar_expression(PROFILE), "roller", radius=rho, name="F")
    m.drive_angle(body, lw.Linear(0.2, TAU), name="turn")
    return m


def offset_flat() -> lw.Mechanism:
    """The profile under a flat-faced follower translating on a line 10 mm off the pivot,
    its face tilted by 0.1 rad."""
    m = lw.Mechanism("expression cam, flat follower")
    body = m.body("cam")
    follower = m.body("follower", (0.01, 0.06), angle=0.1)
    m.revolute(m.ground, body, at=(0, 0), name="O")
    m.prismatic(m.ground, follower, at=(0.01, 0.06), axis=(0, 1), name="slide")
    m.cam_follower(
        body, follower, (0.01, 0.06), lw.curves.polar_expression(PROFILE), "flat", face=(1, 0), name="F"
    )
    m.drive_angle(body, lw.Linear(0.0, TAU), name="turn")
    return m


def rise_return_knife() -> lw.Mechanism:
    """The cycloidal rise-and-return profile, its centre off the pivot, under a radial
    knife-edge follower."""
    m = lw.Mechanism("rise and return, knife edge")
    body = m.body("cam")
    follower = m.body("follower", (0.0, 0.05))
    m.revolute(m.ground, body, at=(0, 0), name="O")
    m.prismatic(m.ground, follower, at=(0.0, 0.05), axis=(0, 1), name="slide")
    m.cam_follower(
        body,
        follower,
        (0.0, 0.05),
        lw.curves.polar_expression(RISE_RETURN, centre=(0.002, 0.0)),
        "knife",
        name="F",
    )
    m.drive_angle(body, lw.Linear(0.0, TAU), name="turn")
    return m


@pytest.mark.parametrize("build", [oscillating_roller, offset_flat, rise_return_knife])
def test_expression_cams_match_the_reference_over_a_turn(build):
    """Every column of q, qd, qdd (s'' holds r''') to 1e-10, as test_cams.compare_with_reference."""
    compare_with_reference(build(), np.linspace(0.0, 1.0, 241))


def test_the_rise_and_return_lifts_its_follower_by_the_motion_law():
    """A radial knife edge on a profile centred on the pivot follows r at the contact:
    y(t) = r(pi/2 - th), the cycloidal rise and return of 10 mm."""
    m = rise_return_knife()
    desc = m.to_dict()
    desc["joints"][-1]["curve"]["centre"] = [0.0, 0.0]
    t = np.linspace(0.0, 1.0, 181)
    r = lw.Model(desc).sweep(t)
    phi = (math.pi / 2 - TAU * t) % TAU
    u = 1 - np.abs(phi - math.pi) / math.pi
    want = 0.04 + 0.01 * (u - np.sin(TAU * u) / TAU)
    assert rel_err(r.body("follower").y, want) <= TOL
    assert np.ptp(r.body("follower").y) == pytest.approx(0.01, rel=1e-12)


# --- refusals, files, units ------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text, match",
    [
        (
            "0.05 + 0.01*(1 - cos(phi)",
            r"joint 'F': curve r '.*': expected '\)' \(for the '\(' at column 13\)",
        ),
        (
            "0.05 + 0.01*cos(t)",
            r"joint 'F': curve r '.*': unknown name 't' at column 17; the variable is 'phi'",
        ),
        (
            "0.025 + 0.05*cos(phi)",
            r"joint 'F': curve r '.*' is -0.025 at phi = 3.14159\d* \(its least value\)",
        ),
        (
            "0.05 + 0.001*ln(1 + cos(phi))",
            r"joint 'F': curve r is not finite at phi = 3.14159\d*: ln\(0\) at column 14",
        ),
        (
            "0.05 + 0.001*phi",
            r"joint 'F': curve r '.*' is not periodic: r\(0\) = 0.05 but r\(2 pi\) = 0.0562",
        ),
        (
            "0.05 + 0.001*sin(phi/2)",
            r"joint 'F': curve r '.*' is not periodic: r'\(0\) = 0.0005 but r'\(2 pi\)",
        ),
    ],
)
def test_bad_expressions_are_refused_naming_the_joint(text, match):
    desc = cam("roller", lw.curves.polar_expression("0.05")).to_dict()
    desc["joints"][-1]["curve"]["r"] = text
    with pytest.raises(lw.ModelError, match=match):
        lw.Model(desc)
    with pytest.raises(ValueError, match="cam_follower joint 'F'"):
        ReferenceModel(desc)


def test_the_builder_parses_at_once():
    with pytest.raises(lw.ExpressionError, match="at column 8") as info:
        lw.curves.polar_expression("0.05 + ", centre=(0, 0))
    assert info.value.column == 8
    assert lw.curves.description(lw.curves.polar_expression("0.05"))["type"] == "polar_expression"


@pytest.mark.parametrize("ext", ["toml", "json"])
def test_model_files_keep_polar_expressions(tmp_path, ext):
    mech = oscillating_roller()
    path = tmp_path / f"cam.{ext}"
    mech.save(str(path))
    assert PROFILE in path.read_text()
    back = lw.Mechanism.load(str(path))
    assert back.to_dict() == mech.to_dict()
    t = np.linspace(0.0, 0.5, 11)
    np.testing.assert_array_equal(back.compile().sweep(t).q, mech.compile().sweep(t).q)


def test_phi_is_in_radians_in_a_model_in_degrees():
    """The model's angles in degrees (the cam's start and its law), r's phi still in rad:
    the same motion, in the engine and in the reference."""
    rad = oscillating_roller().to_dict()
    deg = oscillating_roller().to_dict()
    k = 180.0 / math.pi
    deg["units"] = {"length": "m", "angle": "deg"}
    for b in deg["bodies"]:
        b["theta"] = b["theta"] * k
    deg["drivers"][0]["law"] = {"type": "linear", "value": 0.2 * k, "rate": TAU * k}
    t = np.linspace(0.0, 1.0, 61)
    want = lw.Model(rad).sweep(t)
    got = lw.Model(deg).sweep(t)
    j = want.columns.index("arm.theta")
    for a, b in ((want.q, got.q), (want.qd, got.qd), (want.qdd, got.qdd)):
        assert rel_err(b[:, j], a[:, j]) <= TOL
    ref = ReferenceModel(lw.Mechanism.from_dict(deg)).sweep(t)
    assert rel_err(ref["q"][:, j], want.q[:, j]) <= TOL


def test_the_docs_example_and_messages_are_true():
    text = (Path(__file__).resolve().parent.parent / "docs" / "cams.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    scope: dict = {}
    exec(compile(blocks[1], "docs/cams.md", "exec"), scope)
    lift = scope["lift"]
    assert np.ptp(lift) == pytest.approx(0.01, rel=1e-12)
    assert abs(lift[0]) < 1e-15 and abs(lift[-1]) < 1e-15 and lift[90] == pytest.approx(0.01, rel=1e-12)
    # the refusals shown, each its first line and the one that follows it
    shown = re.search(r"```text\n(joint 'F': curve r.*?)```", text, flags=re.S)
    assert shown
    messages = re.split(r"\n(?=joint)", shown.group(1).strip())
    assert len(messages) == 3
    for message in messages:
        message = " ".join(line.strip() for line in message.splitlines())
        r = re.match(r"joint 'F': curve r '(.*?)'", message)
        assert r
        desc = cam("roller", lw.curves.polar_expression("0.05")).to_dict()
        desc["joints"][-1]["curve"]["r"] = r.group(1)
        with pytest.raises(lw.ModelError) as info:
            lw.Model(desc)
        assert str(info.value) == message
