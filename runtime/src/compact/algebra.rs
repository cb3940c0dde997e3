//! The spatial algebra of the compact kernels, on any [`Real`]: 3-vectors, 3×3 blocks,
//! motion and force vectors as pairs of 3-vectors, rigid-body inertias as mass, first
//! moment and rotational inertia, and articulated inertias as three 3×3 blocks
//! (Featherstone, *Rigid Body Dynamics Algorithms*, ch. 2 and 7). Every function is
//! `#[inline(always)]`: the loops of [`aba`](super::aba) and [`crba`](super::crba) are
//! the only code.

use crate::real::Real;

pub type V3<T> = [T; 3];
pub type M3<T> = [[T; 3]; 3];

#[inline(always)]
pub fn add<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
pub fn sub<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
pub fn scale<T: Real>(k: T, a: V3<T>) -> V3<T> {
    [k * a[0], k * a[1], k * a[2]]
}

/// `a₀ b₀ + a₁ b₁ + a₂ b₂` of six scalar expressions, summed in that order through
/// `mul_add` (the same rounding as the plain sum where `mul_add` is unfused). A macro,
/// not a function: unoptimised, every call would copy its arguments into the caller's
/// frame, and the compact loops on wide duals have large frames already.
macro_rules! dot3 {
    ($a0:expr, $b0:expr, $a1:expr, $b1:expr, $a2:expr, $b2:expr) => {
        $a2.mul_add($b2, $a1.mul_add($b1, $a0 * $b0))
    };
}

#[inline(always)]
pub fn dot<T: Real>(a: V3<T>, b: V3<T>) -> T {
    dot3!(a[0], b[0], a[1], b[1], a[2], b[2])
}

#[inline(always)]
pub fn cross<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [
        a[1].mul_add(b[2], -(a[2] * b[1])),
        a[2].mul_add(b[0], -(a[0] * b[2])),
        a[0].mul_add(b[1], -(a[1] * b[0])),
    ]
}

/// `a · b` of two six-vectors (spatial vectors as their components) as one chain of
/// multiply–adds: on the fused twins one instruction per term.
#[inline(always)]
pub fn dot6<T: Real>(a: [T; 6], b: [T; 6]) -> T {
    (1..6).fold(a[0] * b[0], |s, n| a[n].mul_add(b[n], s))
}

/// A 3×3 block from its nine entries, row by row.
#[inline(always)]
pub fn m3<T: Copy>(x: [T; 9]) -> M3<T> {
    [[x[0], x[1], x[2]], [x[3], x[4], x[5]], [x[6], x[7], x[8]]]
}

/// A 3×3 block's nine entries, row by row.
#[inline(always)]
pub fn flat<T: Copy>(x: &M3<T>) -> [T; 9] {
    let [a, b, c] = *x;
    [a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]]
}

/// `R x`.
#[inline(always)]
pub fn mul<T: Real>(r: &M3<T>, x: V3<T>) -> V3<T> {
    let row = |i: usize| dot3!(r[i][0], x[0], r[i][1], x[1], r[i][2], x[2]);
    [row(0), row(1), row(2)]
}

/// `Rᵀ x`.
#[inline(always)]
pub fn mul_t<T: Real>(r: &M3<T>, x: V3<T>) -> V3<T> {
    let col = |j: usize| dot3!(r[0][j], x[0], r[1][j], x[1], r[2][j], x[2]);
    [col(0), col(1), col(2)]
}

/// `A B`.
#[inline(always)]
pub fn mat_mul<T: Real>(a: &M3<T>, b: &M3<T>) -> M3<T> {
    let e = |i: usize, j: usize| dot3!(a[i][0], b[0][j], a[i][1], b[1][j], a[i][2], b[2][j]);
    [
        [e(0, 0), e(0, 1), e(0, 2)],
        [e(1, 0), e(1, 1), e(1, 2)],
        [e(2, 0), e(2, 1), e(2, 2)],
    ]
}

/// `C Rz(θ)` from `(sin θ, cos θ)`: the first two columns turn, the third stays.
#[inline(always)]
pub fn turn_z<T: Real>(c: &M3<T>, s: T, co: T) -> M3<T> {
    let row = |r: [T; 3]| {
        [
            r[1].mul_add(s, r[0] * co),
            r[1].mul_add(co, -(r[0] * s)),
            r[2],
        ]
    };
    [row(c[0]), row(c[1]), row(c[2])]
}

/// A symmetric 3×3 block `[xx, yy, zz, xy, xz, yz]`.
pub type Sym<T> = [T; 6];

#[inline(always)]
pub fn sym_full<T: Real>(s: &Sym<T>) -> M3<T> {
    [[s[0], s[3], s[4]], [s[3], s[1], s[5]], [s[4], s[5], s[2]]]
}

#[inline(always)]
pub fn sym_mul<T: Real>(s: &Sym<T>, x: V3<T>) -> V3<T> {
    [
        dot3!(s[0], x[0], s[3], x[1], s[4], x[2]),
        dot3!(s[3], x[0], s[1], x[1], s[5], x[2]),
        dot3!(s[4], x[0], s[5], x[1], s[2], x[2]),
    ]
}

/// `R S Rᵀ` of a symmetric `S`.
#[inline(always)]
pub fn sym_rotate<T: Real>(r: &M3<T>, s: &Sym<T>) -> Sym<T> {
    // rows of R S
    let rs = [sym_mul(s, r[0]), sym_mul(s, r[1]), sym_mul(s, r[2])];
    [
        dot(rs[0], r[0]),
        dot(rs[1], r[1]),
        dot(rs[2], r[2]),
        dot(rs[0], r[1]),
        dot(rs[0], r[2]),
        dot(rs[1], r[2]),
    ]
}

/// `R B Rᵀ` of a general `B`.
#[inline(always)]
pub fn rotate<T: Real>(r: &M3<T>, b: &M3<T>) -> M3<T> {
    // (R B)_i = Bᵀ applied to row i of R, as a row
    let rb = [mul_t(b, r[0]), mul_t(b, r[1]), mul_t(b, r[2])];
    [
        [dot(rb[0], r[0]), dot(rb[0], r[1]), dot(rb[0], r[2])],
        [dot(rb[1], r[0]), dot(rb[1], r[1]), dot(rb[1], r[2])],
        [dot(rb[2], r[0]), dot(rb[2], r[1]), dot(rb[2], r[2])],
    ]
}

/// A spatial vector: angular part then linear part (a motion `(ω, v)` or a force
/// `(n, f)`).
#[derive(Clone, Copy, Debug)]
pub struct Spatial<T> {
    pub w: V3<T>,
    pub l: V3<T>,
}

impl<T: Real> Spatial<T> {
    #[inline(always)]
    pub fn zero() -> Self {
        let z = T::cst(0.0);
        Spatial {
            w: [z; 3],
            l: [z; 3],
        }
    }

    /// From its six components, angular first.
    #[inline(always)]
    pub fn of(x: [T; 6]) -> Self {
        Spatial {
            w: [x[0], x[1], x[2]],
            l: [x[3], x[4], x[5]],
        }
    }

    /// Its six components, angular first.
    #[inline(always)]
    pub fn array(self) -> [T; 6] {
        [
            self.w[0], self.w[1], self.w[2], self.l[0], self.l[1], self.l[2],
        ]
    }

    #[inline(always)]
    pub fn plus(self, o: Self) -> Self {
        Spatial {
            w: add(self.w, o.w),
            l: add(self.l, o.l),
        }
    }

    /// A motion from the parent's frame to the child's (`r` the child's axes in the
    /// parent's frame, `p` its origin there).
    #[inline(always)]
    pub fn motion_to_child(self, r: &M3<T>, p: V3<T>) -> Self {
        Spatial {
            w: mul_t(r, self.w),
            l: mul_t(r, sub(self.l, cross(p, self.w))),
        }
    }

    /// A force from the child's frame to the parent's.
    #[inline(always)]
    pub fn force_to_parent(self, r: &M3<T>, p: V3<T>) -> Self {
        let f = mul(r, self.l);
        Spatial {
            w: add(mul(r, self.w), cross(p, f)),
            l: f,
        }
    }

    /// `self ×* f`: the motion's cross product with a force.
    #[inline(always)]
    pub fn cross_force(self, f: Self) -> Self {
        Spatial {
            w: add(cross(self.w, f.w), cross(self.l, f.l)),
            l: cross(self.w, f.l),
        }
    }

    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        dot(self.w, o.w) + dot(self.l, o.l)
    }
}

/// A rigid body's inertia `(m, h, Ī)`: mass, first moment, rotational inertia about the
/// frame's origin.
#[derive(Clone, Copy, Debug)]
pub struct Rigid<T> {
    pub m: T,
    pub h: V3<T>,
    pub i: Sym<T>,
}

impl<T: Real> Rigid<T> {
    /// From its ten numbers `[m, h, Ī]`.
    #[inline(always)]
    pub fn of(x: [T; 10]) -> Self {
        Rigid {
            m: x[0],
            h: [x[1], x[2], x[3]],
            i: [x[4], x[5], x[6], x[7], x[8], x[9]],
        }
    }

    /// Its ten numbers `[m, h, Ī]`.
    #[inline(always)]
    pub fn array(&self) -> [T; 10] {
        let (h, i) = (self.h, self.i);
        [self.m, h[0], h[1], h[2], i[0], i[1], i[2], i[3], i[4], i[5]]
    }

    /// In the parent's frame: `h' = R h + m p`,
    /// `Ī' = R Ī Rᵀ − (p aᵀ + a pᵀ − 2 (a·p) 1) − m (p pᵀ − |p|² 1)` with `a = R h`.
    #[inline(always)]
    pub fn in_parent(&self, r: &M3<T>, p: V3<T>) -> Self {
        let a = mul(r, self.h);
        let ri = sym_rotate(r, &self.i);
        let ap = dot(a, p);
        let pp = dot(p, p);
        let two = T::cst(2.0);
        let diag = self.m.mul_add(pp, two * ap);
        let e = |i: usize, j: usize| (self.m * p[i]).mul_add(p[j], a[i].mul_add(p[j], p[i] * a[j]));
        let m = self.m;
        Rigid {
            m,
            h: [
                m.mul_add(p[0], a[0]),
                m.mul_add(p[1], a[1]),
                m.mul_add(p[2], a[2]),
            ],
            i: [
                ri[0] - e(0, 0) + diag,
                ri[1] - e(1, 1) + diag,
                ri[2] - e(2, 2) + diag,
                ri[3] - e(0, 1),
                ri[4] - e(0, 2),
                ri[5] - e(1, 2),
            ],
        }
    }

    /// `I s` of a motion `s = (ω, v)`: `(Ī ω + h × v, m v − h × ω)` (for a joint along
    /// `z` in the body's frame, `(Ī e_z, e_z × h)` turning and `(h × e_z, m e_z)`
    /// sliding).
    #[inline(always)]
    pub fn times(&self, s: Spatial<T>) -> Spatial<T> {
        let (hv, hw) = (cross(self.h, s.l), cross(self.h, s.w));
        let iw = sym_mul(&self.i, s.w);
        Spatial {
            w: add(iw, hv),
            l: [
                self.m.mul_add(s.l[0], -hw[0]),
                self.m.mul_add(s.l[1], -hw[1]),
                self.m.mul_add(s.l[2], -hw[2]),
            ],
        }
    }
}

/// An articulated-body inertia `[[A, B], [Bᵀ, C]]` (angular rows first), `A` and `C`
/// symmetric; a rigid body's is `[[Ī, h×], [−h×, m 1]]`.
#[derive(Clone, Copy, Debug)]
pub struct Inertia<T> {
    pub a: Sym<T>,
    pub b: M3<T>,
    pub c: Sym<T>,
}

impl<T: Real> Inertia<T> {
    /// A rigid body's: mass, first moment `h` and rotational inertia `Ī` about the origin.
    #[inline(always)]
    pub fn rigid(m: T, h: V3<T>, i: Sym<T>) -> Self {
        let z = T::cst(0.0);
        Inertia {
            a: i,
            b: [[z, -h[2], h[1]], [h[2], z, -h[0]], [-h[1], h[0], z]],
            c: [m, m, m, z, z, z],
        }
    }

    /// `self + ` the rigid body's inertia ([`rigid`](Self::rigid)), its zeros not added.
    #[inline(always)]
    pub fn plus_rigid(&self, m: T, h: V3<T>, i: &Sym<T>) -> Self {
        let (a, b, c) = (&self.a, &self.b, &self.c);
        Inertia {
            a: std::array::from_fn(|k| a[k] + i[k]),
            b: [
                [b[0][0], b[0][1] - h[2], b[0][2] + h[1]],
                [b[1][0] + h[2], b[1][1], b[1][2] - h[0]],
                [b[2][0] - h[1], b[2][1] + h[0], b[2][2]],
            ],
            c: [c[0] + m, c[1] + m, c[2] + m, c[3], c[4], c[5]],
        }
    }

    /// `I x`.
    #[inline(always)]
    pub fn apply(&self, x: Spatial<T>) -> Spatial<T> {
        Spatial {
            w: add(sym_mul(&self.a, x.w), mul(&self.b, x.l)),
            l: add(mul_t(&self.b, x.w), sym_mul(&self.c, x.l)),
        }
    }

    #[inline(always)]
    pub fn add_to(&mut self, o: &Self) {
        for k in 0..6 {
            self.a[k] = self.a[k] + o.a[k];
            self.c[k] = self.c[k] + o.c[k];
        }
        for i in 0..3 {
            for j in 0..3 {
                self.b[i][j] = self.b[i][j] + o.b[i][j];
            }
        }
    }

    /// `I − U Uᵀ / d` with `U = (u_w, u_l)`, `inv = 1 / d`.
    #[inline(always)]
    pub fn minus_rank_one(&self, u: Spatial<T>, inv: T) -> Self {
        let uw = scale(inv, u.w);
        let ul = scale(inv, u.l);
        // s − y x, as (−y) x + s (the same rounding unfused).
        let s = |s: &Sym<T>, x: V3<T>, y: V3<T>| {
            [
                (-y[0]).mul_add(x[0], s[0]),
                (-y[1]).mul_add(x[1], s[1]),
                (-y[2]).mul_add(x[2], s[2]),
                (-y[0]).mul_add(x[1], s[3]),
                (-y[0]).mul_add(x[2], s[4]),
                (-y[1]).mul_add(x[2], s[5]),
            ]
        };
        let mut b = self.b;
        for (i, row) in b.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = (-uw[i]).mul_add(u.l[j], *x);
            }
        }
        Inertia {
            a: s(&self.a, u.w, uw),
            b,
            c: s(&self.c, u.l, ul),
        }
    }

    /// The inertia in the parent's frame, `Xᵀ I X` (`R` the child's axes in the
    /// parent's frame, `p` its origin there).
    // Unoptimised (where debug assertions are on), out of line: inlined, the two
    // variants' temporaries would share one frame of the loop, over a megabyte on wide
    // duals. Optimised, always inlined, so that the fused twins compile it with FMA.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn to_parent(&self, r: &M3<T>, p: V3<T>) -> Self {
        let a = sym_rotate(r, &self.a);
        let b = rotate(r, &self.b);
        let c = sym_rotate(r, &self.c);
        Self::shifted(a, b, c, p)
    }

    /// [`to_parent`](Self::to_parent) of the articulated inertia a revolute joint
    /// passes on, `I^a = I^A − U Uᵀ / D`: its angular `z` row and column vanish
    /// (`I^a S = 0`, `S = e_z`), so `A`'s third row and column and `B`'s third row are not
    /// read, and the rotation of `A` and `B` takes two of `R`'s columns where it took
    /// three (Featherstone, *Rigid Body Dynamics Algorithms*, §7.3).
    // Unoptimised (where debug assertions are on), out of line: inlined, the two
    // variants' temporaries would share one frame of the loop, over a megabyte on wide
    // duals. Optimised, always inlined, so that the fused twins compile it with FMA.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn to_parent_revolute(&self, r: &M3<T>, p: V3<T>) -> Self {
        let (a0, a1, a3) = (self.a[0], self.a[1], self.a[3]);
        // Row i of R A: (R_i0 a0 + R_i1 a3, R_i0 a3 + R_i1 a1, 0).
        let ra = |i: usize| {
            [
                r[i][1].mul_add(a3, r[i][0] * a0),
                r[i][1].mul_add(a1, r[i][0] * a3),
            ]
        };
        let (ra0, ra1, ra2) = (ra(0), ra(1), ra(2));
        let ar = |x: [T; 2], j: usize| x[1].mul_add(r[j][1], x[0] * r[j][0]);
        let a = [
            ar(ra0, 0),
            ar(ra1, 1),
            ar(ra2, 2),
            ar(ra0, 1),
            ar(ra0, 2),
            ar(ra1, 2),
        ];
        // Row i of R B: R_i0 B_0 + R_i1 B_1 (B's rows; its third is zero).
        let b = &self.b;
        let rb = |i: usize| -> V3<T> {
            std::array::from_fn(|k| r[i][1].mul_add(b[1][k], r[i][0] * b[0][k]))
        };
        let (rb0, rb1, rb2) = (rb(0), rb(1), rb(2));
        let b = [
            [dot(rb0, r[0]), dot(rb0, r[1]), dot(rb0, r[2])],
            [dot(rb1, r[0]), dot(rb1, r[1]), dot(rb1, r[2])],
            [dot(rb2, r[0]), dot(rb2, r[1]), dot(rb2, r[2])],
        ];
        let c = sym_rotate(r, &self.c);
        Self::shifted(a, b, c, p)
    }

    /// The blocks `a`, `b`, `c`, already rotated into the parent's axes, shifted by the
    /// child's origin `p` there.
    #[inline(always)]
    fn shifted(a: Sym<T>, b: M3<T>, c: Sym<T>, p: V3<T>) -> Self {
        // Shift by p: B'' = B + p× C, A'' = A + p× Bᵀ + (p× B''ᵀ)ᵀ.
        let cf = sym_full(&c);
        let px = |x: V3<T>| cross(p, x);
        // columns of p× C are p × (columns of C); C symmetric, so its rows.
        let pc = [px(cf[0]), px(cf[1]), px(cf[2])]; // pc[j] = column j of p×C
        let mut b2 = b;
        for (i, row) in b2.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = *x + pc[j][i];
            }
        }
        // p× Bᵀ: column j = p × (row j of B); (p× B''ᵀ)ᵀ: row i = p × (row i of B'').
        let k = [px(b[0]), px(b[1]), px(b[2])]; // k[j] = column j of p×Bᵀ
        let l = [px(b2[0]), px(b2[1]), px(b2[2])]; // l[i] = row i of (p×B''ᵀ)ᵀ
        // entry (i, j) = A_ij + k[j][i] + l[i][j]
        let e = |i: usize, j: usize| k[j][i] + l[i][j];
        Inertia {
            a: [
                a[0] + e(0, 0),
                a[1] + e(1, 1),
                a[2] + e(2, 2),
                a[3] + e(0, 1),
                a[4] + e(0, 2),
                a[5] + e(1, 2),
            ],
            b: b2,
            c,
        }
    }
}
