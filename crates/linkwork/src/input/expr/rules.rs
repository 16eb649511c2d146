//! Every function's derivatives, written once at third order: the rules the tape runs.

/// A value and its derivatives with respect to the variable, [f, f', .., f^(N-1)]:
/// N = 3 in `eval`, 4 in `eval3`.
pub(super) type Derivs<const N: usize> = [f64; N];

/// The jet widened to third order, the derivatives it lacks zero.
#[inline(always)]
pub(super) fn widen<const N: usize>(u: Derivs<N>) -> [f64; 4] {
    std::array::from_fn(|k| if k < N { u[k] } else { 0.0 })
}

/// The first N slots of a third-order jet (N <= 4).
#[inline(always)]
pub(super) fn narrow<const N: usize>(v: [f64; 4]) -> Derivs<N> {
    std::array::from_fn(|k| v[k])
}

/// g(u) from g, g', g'', g''' at u[0] (Faa di Bruno): (g o u)' = g' u',
/// (g o u)'' = g'' u'^2 + g' u'', (g o u)''' = g''' u'^3 + 3 g'' u' u'' + g' u'''.
#[inline(always)]
pub(super) fn chain<const N: usize>(g: [f64; 4], u: Derivs<N>) -> Derivs<N> {
    let [_, u1, u2, u3] = widen(u);
    let [g0, g1, g2, g3] = g;
    narrow([g0, g1 * u1, g2 * u1 * u1 + g1 * u2, g3 * u1 * u1 * u1 + 3.0 * g2 * u1 * u2 + g1 * u3])
}

/// Functions of one argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Fn1 {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Ln,
    Log10,
    Sqrt,
    Abs,
    Neg,
}

/// Functions of two arguments (the binary operators among them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Fn2 {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Atan2,
    Min,
    Max,
    Hypot,
}

/// The names a text may call, with their arity.
pub(super) const FUNCTIONS: [(&str, Func); 20] = [
    ("sin", Func::One(Fn1::Sin)),
    ("cos", Func::One(Fn1::Cos)),
    ("tan", Func::One(Fn1::Tan)),
    ("asin", Func::One(Fn1::Asin)),
    ("acos", Func::One(Fn1::Acos)),
    ("atan", Func::One(Fn1::Atan)),
    ("sinh", Func::One(Fn1::Sinh)),
    ("cosh", Func::One(Fn1::Cosh)),
    ("tanh", Func::One(Fn1::Tanh)),
    ("exp", Func::One(Fn1::Exp)),
    ("ln", Func::One(Fn1::Ln)),
    ("log", Func::One(Fn1::Ln)),
    ("log10", Func::One(Fn1::Log10)),
    ("sqrt", Func::One(Fn1::Sqrt)),
    ("abs", Func::One(Fn1::Abs)),
    ("atan2", Func::Two(Fn2::Atan2)),
    ("min", Func::Two(Fn2::Min)),
    ("max", Func::Two(Fn2::Max)),
    ("pow", Func::Two(Fn2::Pow)),
    ("hypot", Func::Two(Fn2::Hypot)),
];
pub(super) const CONSTANTS: [(&str, f64); 2] = [("pi", std::f64::consts::PI), ("e", std::f64::consts::E)];

#[derive(Debug, Clone, Copy)]
pub(super) enum Func {
    One(Fn1),
    Two(Fn2),
}

impl Fn1 {
    pub(super) fn name(self) -> &'static str {
        match self {
            Fn1::Neg => "unary minus",
            _ => FUNCTIONS
                .iter()
                .find(|(_, f)| matches!(f, Func::One(g) if *g == self))
                .map_or("?", |(n, _)| n),
        }
    }

    /// (g(u), g'(u), g''(u), g'''(u)).
    #[inline(always)]
    pub(super) fn derivatives(self, u: f64) -> [f64; 4] {
        match self {
            Fn1::Neg => [-u, -1.0, 0.0, 0.0],
            Fn1::Sin => {
                let (s, c) = u.sin_cos();
                [s, c, -s, -c]
            }
            Fn1::Cos => {
                let (s, c) = u.sin_cos();
                [c, -s, -c, s]
            }
            Fn1::Tan => {
                // g' = 1 + g^2, g'' = 2 g g', g''' = 2 g'^2 + 2 g g'' = 2 g' (1 + 3 g^2)
                let g = u.tan();
                let g1 = 1.0 + g * g;
                [g, g1, 2.0 * g * g1, 2.0 * g1 * (1.0 + 3.0 * g * g)]
            }
            Fn1::Asin => {
                // w = 1 - u^2: g' = w^-1/2, g'' = u w^-3/2, g''' = (1 + 2 u^2) w^-5/2
                let w = 1.0 - u * u;
                let r = 1.0 / w.sqrt();
                [u.asin(), r, u * r / w, (1.0 + 2.0 * u * u) * r / (w * w)]
            }
            Fn1::Acos => {
                let w = 1.0 - u * u;
                let r = 1.0 / w.sqrt();
                [u.acos(), -r, -u * r / w, -(1.0 + 2.0 * u * u) * r / (w * w)]
            }
            Fn1::Atan => {
                // r = 1 / (1 + u^2): g' = r, g'' = -2 u r^2, g''' = (6 u^2 - 2) r^3
                let r = 1.0 / (1.0 + u * u);
                [u.atan(), r, -2.0 * u * r * r, (6.0 * u * u - 2.0) * r * r * r]
            }
            Fn1::Sinh => {
                let (sh, ch) = (u.sinh(), u.cosh());
                [sh, ch, sh, ch]
            }
            Fn1::Cosh => {
                let (sh, ch) = (u.sinh(), u.cosh());
                [ch, sh, ch, sh]
            }
            Fn1::Tanh => {
                // g' = 1 - g^2, g'' = -2 g g', g''' = -2 g'^2 - 2 g g'' = -2 g' (1 - 3 g^2)
                let g = u.tanh();
                let g1 = 1.0 - g * g;
                [g, g1, -2.0 * g * g1, -2.0 * g1 * (1.0 - 3.0 * g * g)]
            }
            Fn1::Exp => {
                let g = u.exp();
                [g, g, g, g]
            }
            Fn1::Ln => {
                let r = 1.0 / u;
                [u.ln(), r, -r * r, 2.0 * r * r * r]
            }
            Fn1::Log10 => {
                let r = 1.0 / u;
                let k = std::f64::consts::LOG10_E;
                [u.log10(), k * r, -k * r * r, 2.0 * k * r * r * r]
            }
            Fn1::Sqrt => {
                // g' = u^-1/2 / 2, g'' = -u^-3/2 / 4, g''' = 3 u^-5/2 / 8
                let g = u.sqrt();
                let g1 = 0.5 / g;
                let g2 = -0.5 * g1 / u;
                [g, g1, g2, -1.5 * g2 / u]
            }
            Fn1::Abs => {
                // the right derivative at 0
                let s = if u < 0.0 { -1.0 } else { 1.0 };
                [u.abs(), s, 0.0, 0.0]
            }
        }
    }

    #[inline(always)]
    pub(super) fn jet<const N: usize>(self, u: Derivs<N>) -> Derivs<N> {
        if let Fn1::Neg = self {
            return u.map(|v| -v);
        }
        chain(self.derivatives(u[0]), u)
    }
}

impl Fn2 {
    pub(super) fn name(self) -> &'static str {
        match self {
            Fn2::Add => "'+'",
            Fn2::Sub => "'-'",
            Fn2::Mul => "'*'",
            Fn2::Div => "'/'",
            Fn2::Pow => "the power",
            Fn2::Atan2 => "atan2",
            Fn2::Min => "min",
            Fn2::Max => "max",
            Fn2::Hypot => "hypot",
        }
    }

    pub(super) fn commutes(self) -> bool {
        matches!(self, Fn2::Add | Fn2::Mul | Fn2::Min | Fn2::Max | Fn2::Hypot)
    }

    #[inline(always)]
    pub(super) fn jet<const N: usize>(self, a: Derivs<N>, b: Derivs<N>) -> Derivs<N> {
        match self {
            Fn2::Add => std::array::from_fn(|k| a[k] + b[k]),
            Fn2::Sub => std::array::from_fn(|k| a[k] - b[k]),
            Fn2::Mul => {
                // Leibniz: (a b)^(n) = sum over k of C(n, k) a^(k) b^(n-k)
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (widen(a), widen(b));
                narrow([
                    a0 * b0,
                    a1 * b0 + a0 * b1,
                    a2 * b0 + 2.0 * a1 * b1 + a0 * b2,
                    a3 * b0 + 3.0 * (a2 * b1 + a1 * b2) + a0 * b3,
                ])
            }
            Fn2::Div => {
                // q = a / b from q b = a: q' = (a' - q b') / b, q'' = (a'' - 2 q' b' - q b'') / b,
                // q''' = (a''' - 3 q'' b' - 3 q' b'' - q b''') / b
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (widen(a), widen(b));
                let q = a0 / b0;
                let q1 = (a1 - q * b1) / b0;
                let q2 = (a2 - 2.0 * q1 * b1 - q * b2) / b0;
                narrow([q, q1, q2, (a3 - 3.0 * (q2 * b1 + q1 * b2) - q * b3) / b0])
            }
            Fn2::Pow => pow_jet(a, b),
            Fn2::Atan2 => {
                // theta = atan2(y, x): theta' = n / d with n = x y' - y x', d = x^2 + y^2, so
                // n' = x y'' - y x'', n'' = x' y'' - y' x'' + x y''' - y x''',
                // d' = 2 (x x' + y y'), d'' = 2 (x'^2 + x x'' + y'^2 + y y''); then the
                // quotient rule as for '/'
                let ([y0, y1, y2, y3], [x0, x1, x2, x3]) = (widen(a), widen(b));
                let d = x0 * x0 + y0 * y0;
                let (n0, n1) = (x0 * y1 - y0 * x1, x0 * y2 - y0 * x2);
                let n2 = x1 * y2 - y1 * x2 + x0 * y3 - y0 * x3;
                let (d1, d2) = (2.0 * (x0 * x1 + y0 * y1), 2.0 * (x1 * x1 + x0 * x2 + y1 * y1 + y0 * y2));
                let w1 = n0 / d;
                let w2 = (n1 - w1 * d1) / d;
                narrow([y0.atan2(x0), w1, w2, (n2 - 2.0 * w2 * d1 - w1 * d2) / d])
            }
            Fn2::Min => {
                if b[0] < a[0] {
                    b
                } else {
                    a
                }
            }
            Fn2::Max => {
                if b[0] > a[0] {
                    b
                } else {
                    a
                }
            }
            Fn2::Hypot => {
                // h^2 = a^2 + b^2 differentiated: h h' = a a' + b b',
                // h h'' + h'^2 = a a'' + a'^2 + b b'' + b'^2,
                // h h''' + 3 h' h'' = a a''' + 3 a' a'' + b b''' + 3 b' b''
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (widen(a), widen(b));
                let h = a0.hypot(b0);
                let h1 = (a0 * a1 + b0 * b1) / h;
                let h2 = (a1 * a1 + a0 * a2 + b1 * b1 + b0 * b2 - h1 * h1) / h;
                let h3 = (3.0 * (a1 * a2 + b1 * b2) + a0 * a3 + b0 * b3 - 3.0 * h1 * h2) / h;
                narrow([h, h1, h2, h3])
            }
        }
    }
}

/// a^b on jets: the power rule when b is constant (any sign of a), exp(b ln a) otherwise.
#[inline(always)]
pub(super) fn pow_jet<const N: usize>(a: Derivs<N>, b: Derivs<N>) -> Derivs<N> {
    if b[1..].iter().all(|v| *v == 0.0) {
        return powc_jet(a, b[0]);
    }
    // f = exp(l), l = b ln a: f' = f l', f'' = f (l'^2 + l''), f''' = f (l'^3 + 3 l' l'' + l''')
    let [_, l1, l2, l3] = widen(Fn2::Mul.jet(b, Fn1::Ln.jet(a)));
    let f = a[0].powf(b[0]);
    narrow([f, f * l1, f * (l1 * l1 + l2), f * (l1 * l1 * l1 + 3.0 * l1 * l2 + l3)])
}

/// a^n for a constant n: g = a^n has g^(k) = n (n - 1) .. (n - k + 1) a^(n-k).
#[inline(always)]
pub(super) fn powc_jet<const N: usize>(a: Derivs<N>, n: f64) -> Derivs<N> {
    if n == 0.0 {
        return narrow([1.0, 0.0, 0.0, 0.0]);
    }
    let (p0, p1, p2, p3) = if n == n.trunc() && n.abs() < 1024.0 {
        let k = n as i32;
        (a[0].powi(k), a[0].powi(k - 1), a[0].powi(k - 2), a[0].powi(k - 3))
    } else {
        (a[0].powf(n), a[0].powf(n - 1.0), a[0].powf(n - 2.0), a[0].powf(n - 3.0))
    };
    // a factor n (n - 1) .. that vanishes (n = 1, 2) drops its term: at a = 0 its power of
    // a is infinite, and 0 * inf must not become NaN
    let (c2, c3) = (n * (n - 1.0), n * (n - 1.0) * (n - 2.0));
    let g2 = if c2 == 0.0 { 0.0 } else { c2 * p2 };
    let g3 = if c3 == 0.0 { 0.0 } else { c3 * p3 };
    chain([p0, n * p1, g2, g3], a)
}
