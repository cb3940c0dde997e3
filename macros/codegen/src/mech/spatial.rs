//! Symbolic 3-vectors, 3×3 matrices and spatial (6D) algebra on the DAG, after
//! Featherstone, *Rigid Body Dynamics Algorithms* (2008), ch. 2: motion vectors
//! `(ω, v)`, force vectors `(n, f)`, Plücker transforms `X = (E, r)` and rigid-body
//! inertias `(m, h, Ī)` with `h = m c` and `Ī` the rotational inertia about the origin.
//! All arithmetic goes through the folding constructors of [`Graph`], so structural
//! zeros of a scene never reach the emitted code.

use crate::sym::{Graph, Id};

pub type V3 = [Id; 3];
pub type M3 = [[Id; 3]; 3];

pub fn v3_const(g: &mut Graph, v: [f64; 3]) -> V3 {
    v.map(|x| g.constant(x))
}

pub fn v3_zero(g: &mut Graph) -> V3 {
    v3_const(g, [0.0; 3])
}

pub fn add3(g: &mut Graph, a: V3, b: V3) -> V3 {
    [g.add(a[0], b[0]), g.add(a[1], b[1]), g.add(a[2], b[2])]
}

pub fn sub3(g: &mut Graph, a: V3, b: V3) -> V3 {
    [g.sub(a[0], b[0]), g.sub(a[1], b[1]), g.sub(a[2], b[2])]
}

pub fn scale3(g: &mut Graph, k: Id, a: V3) -> V3 {
    [g.mul(k, a[0]), g.mul(k, a[1]), g.mul(k, a[2])]
}

pub fn dot3(g: &mut Graph, a: V3, b: V3) -> Id {
    g.dot(&a, &b)
}

pub fn cross(g: &mut Graph, a: V3, b: V3) -> V3 {
    let mut out = [a[0]; 3];
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let l = g.mul(a[j], b[k]);
        let r = g.mul(a[k], b[j]);
        out[i] = g.sub(l, r);
    }
    out
}

pub fn identity(g: &mut Graph) -> M3 {
    let (o, z) = (g.one(), g.zero());
    [[o, z, z], [z, o, z], [z, z, o]]
}

/// `A b`.
pub fn mat_vec(g: &mut Graph, a: &M3, b: V3) -> V3 {
    [g.dot(&a[0], &b), g.dot(&a[1], &b), g.dot(&a[2], &b)]
}

pub fn transpose(a: &M3) -> M3 {
    let mut t = *a;
    for (i, row) in a.iter().enumerate() {
        for (j, &x) in row.iter().enumerate() {
            t[j][i] = x;
        }
    }
    t
}

/// `Aᵀ b`.
pub fn mat_t_vec(g: &mut Graph, a: &M3, b: V3) -> V3 {
    mat_vec(g, &transpose(a), b)
}

pub fn mat_mul(g: &mut Graph, a: &M3, b: &M3) -> M3 {
    let bt = transpose(b);
    let mut out = *a;
    for i in 0..3 {
        for j in 0..3 {
            out[i][j] = g.dot(&a[i], &bt[j]);
        }
    }
    out
}

pub fn mat_add(g: &mut Graph, a: &M3, b: &M3) -> M3 {
    let mut out = *a;
    for i in 0..3 {
        for j in 0..3 {
            out[i][j] = g.add(a[i][j], b[i][j]);
        }
    }
    out
}

/// Rotation by angle `(s, c) = (sin θ, cos θ)` about a constant unit axis `a`
/// (Rodrigues: `a aᵀ + c (1 − a aᵀ) + s [a×]`, written so constant entries fold).
pub fn axis_rotation(g: &mut Graph, a: [f64; 3], s: Id, c: Id) -> M3 {
    let cross = [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
    let mut out = identity(g);
    for i in 0..3 {
        for j in 0..3 {
            let outer = a[i] * a[j];
            let delta = if i == j { 1.0 } else { 0.0 };
            let k0 = g.constant(outer);
            let kc = g.constant(delta - outer);
            let ks = g.constant(cross[i][j]);
            let tc = g.mul(kc, c);
            let ts = g.mul(ks, s);
            let t = g.add(tc, ts);
            out[i][j] = g.add(k0, t);
        }
    }
    out
}

/// A spatial motion vector: angular `w`, linear `v`.
#[derive(Clone, Copy)]
pub struct Motion {
    pub w: V3,
    pub v: V3,
}

/// A spatial force vector: moment `n`, force `f`.
#[derive(Clone, Copy)]
pub struct Force {
    pub n: V3,
    pub f: V3,
}

impl Motion {
    pub fn zero(g: &mut Graph) -> Motion {
        Motion {
            w: v3_zero(g),
            v: v3_zero(g),
        }
    }

    pub fn add(self, g: &mut Graph, o: Motion) -> Motion {
        Motion {
            w: add3(g, self.w, o.w),
            v: add3(g, self.v, o.v),
        }
    }

    pub fn scale(self, g: &mut Graph, k: Id) -> Motion {
        Motion {
            w: scale3(g, k, self.w),
            v: scale3(g, k, self.v),
        }
    }

    /// `self ×ₘ m` (Featherstone eq. 2.31).
    pub fn cross_motion(self, g: &mut Graph, m: Motion) -> Motion {
        let w = cross(g, self.w, m.w);
        let a = cross(g, self.w, m.v);
        let b = cross(g, self.v, m.w);
        Motion {
            w,
            v: add3(g, a, b),
        }
    }

    /// `self ×* f` (Featherstone eq. 2.32).
    pub fn cross_force(self, g: &mut Graph, f: Force) -> Force {
        let a = cross(g, self.w, f.n);
        let b = cross(g, self.v, f.f);
        Force {
            n: add3(g, a, b),
            f: cross(g, self.w, f.f),
        }
    }

    /// `self · f`: power of a force on a motion.
    pub fn dot_force(self, g: &mut Graph, f: Force) -> Id {
        let a = dot3(g, self.w, f.n);
        let b = dot3(g, self.v, f.f);
        g.add(a, b)
    }
}

impl Force {
    pub fn add(self, g: &mut Graph, o: Force) -> Force {
        Force {
            n: add3(g, self.n, o.n),
            f: add3(g, self.f, o.f),
        }
    }

    pub fn sub(self, g: &mut Graph, o: Force) -> Force {
        Force {
            n: sub3(g, self.n, o.n),
            f: sub3(g, self.f, o.f),
        }
    }
}

/// Plücker transform from a parent frame to a child frame: `e` rotates parent
/// coordinates into child coordinates, `r` is the child origin in parent coordinates.
#[derive(Clone, Copy)]
pub struct Xform {
    pub e: M3,
    pub r: V3,
}

impl Xform {
    /// Motion in parent coordinates → child coordinates: `(E ω, E (v − r × ω))`.
    pub fn apply_motion(&self, g: &mut Graph, m: Motion) -> Motion {
        let w = mat_vec(g, &self.e, m.w);
        let rw = cross(g, self.r, m.w);
        let d = sub3(g, m.v, rw);
        Motion {
            w,
            v: mat_vec(g, &self.e, d),
        }
    }

    /// Force in child coordinates → parent coordinates (`Xᵀ f`): `(Eᵀ n + r × Eᵀ f, Eᵀ f)`.
    pub fn apply_force_t(&self, g: &mut Graph, f: Force) -> Force {
        let ff = mat_t_vec(g, &self.e, f.f);
        let nn = mat_t_vec(g, &self.e, f.n);
        let rf = cross(g, self.r, ff);
        Force {
            n: add3(g, nn, rf),
            f: ff,
        }
    }
}

/// Rigid-body inertia about a frame's origin: mass `m`, first moment `h = m c`,
/// rotational inertia `ibar` about the origin.
#[derive(Clone, Copy)]
pub struct Inertia {
    pub m: Id,
    pub h: V3,
    pub ibar: M3,
}

impl Inertia {
    /// From mass, centre of mass and inertia about the centre of mass (parallel axes).
    pub fn from_com(g: &mut Graph, m: Id, c: V3, ic: &M3) -> Inertia {
        let h = scale3(g, m, c);
        // Ī = I_c + m (|c|² 1 − c cᵀ) = I_c + |c|²·m 1 − h cᵀ
        let cc = dot3(g, c, c);
        let mcc = g.mul(m, cc);
        let mut ibar = *ic;
        for i in 0..3 {
            for j in 0..3 {
                let outer = g.mul(h[i], c[j]);
                let mut t = g.sub(ic[i][j], outer);
                if i == j {
                    t = g.add(t, mcc);
                }
                ibar[i][j] = t;
            }
        }
        Inertia { m, h, ibar }
    }

    /// `I m` (Featherstone eq. 2.63 in `(m, h, Ī)` form): `(Ī ω + h × v, m v − h × ω)`.
    pub fn apply(&self, g: &mut Graph, m: Motion) -> Force {
        let iw = mat_vec(g, &self.ibar, m.w);
        let hv = cross(g, self.h, m.v);
        let mv = scale3(g, self.m, m.v);
        let hw = cross(g, self.h, m.w);
        Force {
            n: add3(g, iw, hv),
            f: sub3(g, mv, hw),
        }
    }

    pub fn add(&self, g: &mut Graph, o: &Inertia) -> Inertia {
        Inertia {
            m: g.add(self.m, o.m),
            h: add3(g, self.h, o.h),
            ibar: mat_add(g, &self.ibar, &o.ibar),
        }
    }

    /// This inertia (in child coordinates) expressed in parent coordinates, `Xᵀ I X`:
    /// `h_p = Eᵀ h + m r`, `Ī_p = Eᵀ Ī E − [r×][(Eᵀh)×] − [h_p×][r×]`.
    pub fn to_parent(&self, g: &mut Graph, x: &Xform) -> Inertia {
        let u = mat_t_vec(g, &x.e, self.h);
        let mr = scale3(g, self.m, x.r);
        let hp = add3(g, u, mr);
        let et = transpose(&x.e);
        let tmp = mat_mul(g, &et, &self.ibar);
        let rot = mat_mul(g, &tmp, &x.e);
        // [a×][b×] = b aᵀ − (a·b) 1, so −[r×][u×] − [h_p×][r×] = −u rᵀ − r h_pᵀ + (r·u + h_p·r) 1.
        let ru = dot3(g, x.r, u);
        let hr = dot3(g, hp, x.r);
        let d = g.add(ru, hr);
        let mut ibar = rot;
        for i in 0..3 {
            for j in 0..3 {
                let a = g.mul(u[i], x.r[j]);
                let b = g.mul(x.r[i], hp[j]);
                let ab = g.add(a, b);
                let mut t = g.sub(rot[i][j], ab);
                if i == j {
                    t = g.add(t, d);
                }
                ibar[i][j] = t;
            }
        }
        Inertia {
            m: self.m,
            h: hp,
            ibar,
        }
    }
}
