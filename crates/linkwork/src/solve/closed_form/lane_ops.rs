//! The lanes' arithmetic on `LANES` numbers at once: IEEE additions, products, quotients,
//! square roots, absolute values and comparisons, each lane rounded as the scalar
//! operation rounds it (no fused multiply-add), so a lane's figures are its design's
//! scalar figures bit for bit. Two sets of the same operations: AVX2 registers (`pulp`'s
//! `V3`, chosen at run time where the machine has it), two of them for the eight lanes,
//! and plain arrays (elsewhere).
//!
//! `min` and `max` are the x86 instructions' (`a < b ? a : b`, `a > b ? a : b`: the second
//! operand where either is NaN), in both sets; on numbers that are not NaN they are
//! `f64::min` and `f64::max`. The lanes take them only where a NaN misses the lane anyway.

/// Designs stepped side by side: two AVX2 registers of four f64. A lane's step is a
/// chain of dependent quotients and square roots whose latency, not the divider's
/// throughput, bounds one register's step; two independent chains fill it.
pub const LANES: usize = 8;
/// One number in every lane.
pub type V = [f64; LANES];

/// The operations the lanes take, on `F` (LANES numbers) and `M` (LANES truth values).
pub trait Ops: Copy {
    type F: Copy;
    type M: Copy;
    fn splat(self, x: f64) -> Self::F;
    fn load(self, v: &V) -> Self::F;
    fn store(self, x: Self::F) -> V;
    fn add(self, a: Self::F, b: Self::F) -> Self::F;
    fn sub(self, a: Self::F, b: Self::F) -> Self::F;
    fn mul(self, a: Self::F, b: Self::F) -> Self::F;
    fn div(self, a: Self::F, b: Self::F) -> Self::F;
    fn sqrt(self, a: Self::F) -> Self::F;
    fn abs(self, a: Self::F) -> Self::F;
    fn min(self, a: Self::F, b: Self::F) -> Self::F;
    fn max(self, a: Self::F, b: Self::F) -> Self::F;
    /// a < b (false where either is NaN)
    fn lt(self, a: Self::F, b: Self::F) -> Self::M;
    /// a <= b (false where either is NaN)
    fn le(self, a: Self::F, b: Self::F) -> Self::M;
    fn is_nan(self, a: Self::F) -> Self::M;
    fn or(self, a: Self::M, b: Self::M) -> Self::M;
    fn not(self, a: Self::M) -> Self::M;
    fn mask(self, b: [bool; LANES]) -> Self::M;
    fn bits(self, m: Self::M) -> [bool; LANES];
}

/// The operations on plain arrays, lane by lane.
#[derive(Debug, Clone, Copy)]
pub struct Plain;

impl Ops for Plain {
    type F = V;
    type M = [bool; LANES];
    #[inline(always)]
    fn splat(self, x: f64) -> V {
        [x; LANES]
    }
    #[inline(always)]
    fn load(self, v: &V) -> V {
        *v
    }
    #[inline(always)]
    fn store(self, x: V) -> V {
        x
    }
    #[inline(always)]
    fn add(self, a: V, b: V) -> V {
        std::array::from_fn(|j| a[j] + b[j])
    }
    #[inline(always)]
    fn sub(self, a: V, b: V) -> V {
        std::array::from_fn(|j| a[j] - b[j])
    }
    #[inline(always)]
    fn mul(self, a: V, b: V) -> V {
        std::array::from_fn(|j| a[j] * b[j])
    }
    #[inline(always)]
    fn div(self, a: V, b: V) -> V {
        std::array::from_fn(|j| a[j] / b[j])
    }
    #[inline(always)]
    fn sqrt(self, a: V) -> V {
        a.map(f64::sqrt)
    }
    #[inline(always)]
    fn abs(self, a: V) -> V {
        a.map(f64::abs)
    }
    #[inline(always)]
    fn min(self, a: V, b: V) -> V {
        std::array::from_fn(|j| if a[j] < b[j] { a[j] } else { b[j] })
    }
    #[inline(always)]
    fn max(self, a: V, b: V) -> V {
        std::array::from_fn(|j| if a[j] > b[j] { a[j] } else { b[j] })
    }
    #[inline(always)]
    fn lt(self, a: V, b: V) -> [bool; LANES] {
        std::array::from_fn(|j| a[j] < b[j])
    }
    #[inline(always)]
    fn le(self, a: V, b: V) -> [bool; LANES] {
        std::array::from_fn(|j| a[j] <= b[j])
    }
    #[inline(always)]
    fn is_nan(self, a: V) -> [bool; LANES] {
        a.map(f64::is_nan)
    }
    #[inline(always)]
    fn or(self, a: [bool; LANES], b: [bool; LANES]) -> [bool; LANES] {
        std::array::from_fn(|j| a[j] | b[j])
    }
    #[inline(always)]
    fn not(self, a: [bool; LANES]) -> [bool; LANES] {
        a.map(|x| !x)
    }
    #[inline(always)]
    fn mask(self, b: [bool; LANES]) -> [bool; LANES] {
        b
    }
    #[inline(always)]
    fn bits(self, m: [bool; LANES]) -> [bool; LANES] {
        m
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{Ops, LANES, V};
    use pulp::x86::V3;
    use pulp::{f64x4, m64, m64x4, Simd};

    /// Two AVX2 registers (four f64 each; lanes 0-3 and 4-7): the token says the machine
    /// has them. Each operation is the register's on both halves.
    impl Ops for V3 {
        type F = (f64x4, f64x4);
        type M = (m64x4, m64x4);
        #[inline(always)]
        fn splat(self, x: f64) -> Self::F {
            (self.splat_f64s(x), self.splat_f64s(x))
        }
        #[inline(always)]
        fn load(self, v: &V) -> Self::F {
            (f64x4(v[0], v[1], v[2], v[3]), f64x4(v[4], v[5], v[6], v[7]))
        }
        #[inline(always)]
        fn store(self, (x, y): Self::F) -> V {
            [x.0, x.1, x.2, x.3, y.0, y.1, y.2, y.3]
        }
        #[inline(always)]
        fn add(self, a: Self::F, b: Self::F) -> Self::F {
            (self.add_f64s(a.0, b.0), self.add_f64s(a.1, b.1))
        }
        #[inline(always)]
        fn sub(self, a: Self::F, b: Self::F) -> Self::F {
            (self.sub_f64s(a.0, b.0), self.sub_f64s(a.1, b.1))
        }
        #[inline(always)]
        fn mul(self, a: Self::F, b: Self::F) -> Self::F {
            (self.mul_f64s(a.0, b.0), self.mul_f64s(a.1, b.1))
        }
        #[inline(always)]
        fn div(self, a: Self::F, b: Self::F) -> Self::F {
            (self.div_f64s(a.0, b.0), self.div_f64s(a.1, b.1))
        }
        #[inline(always)]
        fn sqrt(self, a: Self::F) -> Self::F {
            (self.sqrt_f64s(a.0), self.sqrt_f64s(a.1))
        }
        #[inline(always)]
        fn abs(self, a: Self::F) -> Self::F {
            (self.abs_f64s(a.0), self.abs_f64s(a.1))
        }
        #[inline(always)]
        fn min(self, a: Self::F, b: Self::F) -> Self::F {
            (self.min_f64s(a.0, b.0), self.min_f64s(a.1, b.1))
        }
        #[inline(always)]
        fn max(self, a: Self::F, b: Self::F) -> Self::F {
            (self.max_f64s(a.0, b.0), self.max_f64s(a.1, b.1))
        }
        #[inline(always)]
        fn lt(self, a: Self::F, b: Self::F) -> Self::M {
            (self.less_than_f64s(a.0, b.0), self.less_than_f64s(a.1, b.1))
        }
        #[inline(always)]
        fn le(self, a: Self::F, b: Self::F) -> Self::M {
            (self.less_than_or_equal_f64s(a.0, b.0), self.less_than_or_equal_f64s(a.1, b.1))
        }
        #[inline(always)]
        fn is_nan(self, a: Self::F) -> Self::M {
            (self.not_m64s(self.equal_f64s(a.0, a.0)), self.not_m64s(self.equal_f64s(a.1, a.1)))
        }
        #[inline(always)]
        fn or(self, a: Self::M, b: Self::M) -> Self::M {
            (self.or_m64s(a.0, b.0), self.or_m64s(a.1, b.1))
        }
        #[inline(always)]
        fn not(self, a: Self::M) -> Self::M {
            (self.not_m64s(a.0), self.not_m64s(a.1))
        }
        #[inline(always)]
        fn mask(self, b: [bool; LANES]) -> Self::M {
            let m =
                |k: usize| m64x4(m64::new(b[k]), m64::new(b[k + 1]), m64::new(b[k + 2]), m64::new(b[k + 3]));
            (m(0), m(4))
        }
        #[inline(always)]
        fn bits(self, (m, n): Self::M) -> [bool; LANES] {
            let (a, b) = (m, n);
            [
                a.0.is_set(),
                a.1.is_set(),
                a.2.is_set(),
                a.3.is_set(),
                b.0.is_set(),
                b.1.is_set(),
                b.2.is_set(),
                b.3.is_set(),
            ]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both sets give the same bits, and the scalar operations' bits, on numbers of every
    /// kind (zeros, subnormals, NaN, infinities, ordinary numbers of both signs).
    #[test]
    fn both_sets_are_the_scalar_operations() {
        let special = [0.0, -0.0, 1e-310, -1e-310, f64::NAN, f64::INFINITY, -f64::INFINITY, 1.0, -2.5];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            if state % 5 == 0 {
                special[(state >> 8) as usize % special.len()]
            } else {
                (state >> 11) as f64 / (1u64 << 40) as f64 - 4096.0
            }
        };
        let bits = |v: V| v.map(f64::to_bits);
        for _ in 0..20_000 {
            let a: V = std::array::from_fn(|_| next());
            let b: V = std::array::from_fn(|_| next());
            let p = Plain;
            let scalar: [V; 5] = [
                std::array::from_fn(|j| a[j] + b[j]),
                std::array::from_fn(|j| a[j] - b[j]),
                std::array::from_fn(|j| a[j] * b[j]),
                std::array::from_fn(|j| a[j] / b[j]),
                std::array::from_fn(|j| a[j].abs().sqrt()),
            ];
            let plain = [p.add(a, b), p.sub(a, b), p.mul(a, b), p.div(a, b), p.sqrt(p.abs(a))];
            for (s, q) in scalar.iter().zip(&plain) {
                assert_eq!(bits(*s), bits(*q));
            }
            // on numbers, min and max are f64's
            for j in 0..LANES {
                if !a[j].is_nan() && !b[j].is_nan() && a[j] != b[j] {
                    assert_eq!(p.min(a, b)[j], a[j].min(b[j]));
                    assert_eq!(p.max(a, b)[j], a[j].max(b[j]));
                }
            }
            #[cfg(target_arch = "x86_64")]
            if let Some(v) = pulp::x86::V3::try_new() {
                let (x, y) = (v.load(&a), v.load(&b));
                let wide = [v.add(x, y), v.sub(x, y), v.mul(x, y), v.div(x, y), v.sqrt(v.abs(x))];
                for (q, w) in plain.iter().zip(wide) {
                    assert_eq!(bits(*q), bits(v.store(w)));
                }
                assert_eq!(bits(p.min(a, b)), bits(v.store(v.min(x, y))));
                assert_eq!(bits(p.max(a, b)), bits(v.store(v.max(x, y))));
                assert_eq!(p.bits(p.lt(a, b)), v.bits(v.lt(x, y)));
                assert_eq!(p.bits(p.le(a, b)), v.bits(v.le(x, y)));
                assert_eq!(p.bits(p.or(p.is_nan(a), p.lt(a, b))), v.bits(v.or(v.is_nan(x), v.lt(x, y))));
                assert_eq!(bits(p.splat(a[0])), bits(v.store(v.splat(a[0]))));
                let m = p.lt(a, b);
                assert_eq!(p.bits(p.not(m)), v.bits(v.not(v.mask(m))));
            }
        }
    }
}
