//! Butcher tableaus as data, each with its source, and the Dormand–Prince continuous
//! extension. `tests` checks every tableau against the order conditions (rooted trees).

/// A Runge–Kutta method `c | A | bᵀ` with an optional embedded `b̂ᵀ`.
///
/// `a[i]` holds row `i` of `A` up to its last non-zero entry (explicit methods: `i`
/// entries; diagonally implicit: `i + 1`); missing entries are zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ButcherTableau {
    pub name: &'static str,
    pub citation: &'static str,
    pub a: &'static [&'static [f64]],
    pub b: &'static [f64],
    pub c: &'static [f64],
    /// Weights of the embedded method, for the error estimate `h Σ (b_i − b̂_i) k_i`.
    pub b_hat: Option<&'static [f64]>,
    pub order: u32,
    pub embedded_order: Option<u32>,
}

impl ButcherTableau {
    pub fn stages(&self) -> usize {
        self.b.len()
    }

    /// `A_ij` (zero outside the stored part).
    pub fn a(&self, i: usize, j: usize) -> f64 {
        self.a[i].get(j).copied().unwrap_or(0.0)
    }

    /// `b_i − b̂_i`, the error weights (empty without an embedded method).
    pub fn error_weights(&self) -> Vec<f64> {
        match self.b_hat {
            Some(bh) => self.b.iter().zip(bh).map(|(b, bh)| b - bh).collect(),
            None => Vec::new(),
        }
    }
}

/// The classic fourth-order Runge–Kutta method.
pub const RK4: ButcherTableau = ButcherTableau {
    name: "RK4",
    citation: "Kutta (1901); Hairer, Nørsett & Wanner, Solving ODEs I, §II.1",
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    c: &[0.0, 0.5, 0.5, 1.0],
    b_hat: None,
    order: 4,
    embedded_order: None,
};

/// Dormand–Prince 5(4), first-same-as-last (the 7th stage is `f(t + h, y_1)`).
pub const DOPRI5: ButcherTableau = ButcherTableau {
    name: "Dormand–Prince 5(4)",
    citation: "Dormand & Prince, J. Comput. Appl. Math. 6 (1980) 19–26; Hairer, Nørsett & \
               Wanner, Solving ODEs I, §II.5, Table 5.2",
    a: &[
        &[],
        &[1.0 / 5.0],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
        &[
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ],
    b: &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ],
    c: &[0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    b_hat: Some(&[
        5179.0 / 57600.0,
        0.0,
        7571.0 / 16695.0,
        393.0 / 640.0,
        -92097.0 / 339200.0,
        187.0 / 2100.0,
        1.0 / 40.0,
    ]),
    order: 5,
    embedded_order: Some(4),
};

/// Coefficients `d_i` of the Dormand–Prince continuous extension (Hairer, Nørsett &
/// Wanner, *Solving ODEs I*, §II.6, dense output of DOPRI5, and the `CONTD5` routine
/// of Hairer's `dopri5.f`): `r5 = h Σ d_i k_i`.
pub const DOPRI5_DENSE: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Dormand–Prince continuous extension at `θ ∈ [0, 1]` of one component, from the step's
/// endpoints `y0, y1`, derivatives `f0 = k1, f1 = k7` and `r5 = h Σ d_i k_i`:
/// `y0 + θ (r2 + (1 − θ)(r3 + θ (r4 + (1 − θ) r5)))` with `r2 = y1 − y0`,
/// `r3 = h f0 − r2`, `r4 = r2 − h f1 − r3`.
pub fn dopri5_dense(theta: f64, h: f64, y0: f64, y1: f64, f0: f64, f1: f64, r5: f64) -> f64 {
    let r2 = y1 - y0;
    let r3 = h * f0 - r2;
    let r4 = r2 - h * f1 - r3;
    let s = 1.0 - theta;
    y0 + theta * (r2 + s * (r3 + theta * (r4 + s * r5)))
}

/// Hairer–Wanner's SDIRK4: 5 stages, γ = 1/4, order 4 with an embedded order-3 method,
/// L-stable and stiffly accurate (`b` is the last row of `A`).
pub const SDIRK4: ButcherTableau = ButcherTableau {
    name: "SDIRK4 (γ = 1/4)",
    citation: "Hairer & Wanner, Solving ODEs II, 2nd ed., §IV.6, Table 6.5 (γ = 1/4); \
               Hairer's code SDIRK4",
    a: &[
        &[1.0 / 4.0],
        &[1.0 / 2.0, 1.0 / 4.0],
        &[17.0 / 50.0, -1.0 / 25.0, 1.0 / 4.0],
        &[371.0 / 1360.0, -137.0 / 2720.0, 15.0 / 544.0, 1.0 / 4.0],
        &[
            25.0 / 24.0,
            -49.0 / 48.0,
            125.0 / 16.0,
            -85.0 / 12.0,
            1.0 / 4.0,
        ],
    ],
    b: &[
        25.0 / 24.0,
        -49.0 / 48.0,
        125.0 / 16.0,
        -85.0 / 12.0,
        1.0 / 4.0,
    ],
    c: &[1.0 / 4.0, 3.0 / 4.0, 11.0 / 20.0, 1.0 / 2.0, 1.0],
    b_hat: Some(&[59.0 / 48.0, -17.0 / 96.0, 225.0 / 32.0, -85.0 / 12.0, 0.0]),
    order: 4,
    embedded_order: Some(3),
};

/// Every tableau of the crate, for tests and reports.
pub const ALL: [&ButcherTableau; 3] = [&RK4, &DOPRI5, &SDIRK4];

#[cfg(test)]
mod tests {
    //! Order conditions `bᵀ Φ(t) = 1/γ(t)` over all rooted trees `t` up to the order
    //! (Butcher; Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.2, Theorem 2.13).
    use super::*;

    /// A rooted tree as the sorted list of its subtrees.
    #[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
    struct Tree(Vec<Tree>);

    impl Tree {
        fn order(&self) -> usize {
            1 + self.0.iter().map(Tree::order).sum::<usize>()
        }
        /// Density γ(t) = |t| Π γ(t_k).
        fn density(&self) -> f64 {
            self.order() as f64 * self.0.iter().map(Tree::density).product::<f64>()
        }
        /// All trees obtained by attaching one new leaf to some node.
        fn grow(&self) -> Vec<Tree> {
            let mut out = vec![{
                let mut children = self.0.clone();
                children.push(Tree(vec![]));
                children.sort();
                Tree(children)
            }];
            for (i, child) in self.0.iter().enumerate() {
                for grown in child.grow() {
                    let mut children = self.0.clone();
                    children[i] = grown;
                    children.sort();
                    out.push(Tree(children));
                }
            }
            out
        }
        /// Elementary weight vector Φ_i(t) = Π_k (A Φ(t_k))_i.
        fn weights(&self, t: &ButcherTableau, a: &dyn Fn(usize, usize) -> f64) -> Vec<f64> {
            let s = t.stages();
            let mut phi = vec![1.0; s];
            for child in &self.0 {
                let w = child.weights(t, a);
                for (i, p) in phi.iter_mut().enumerate() {
                    *p *= (0..s).map(|j| a(i, j) * w[j]).sum::<f64>();
                }
            }
            phi
        }
    }

    fn trees_up_to(order: usize) -> Vec<Tree> {
        let mut all = vec![Tree(vec![])];
        let mut current = all.clone();
        for _ in 1..order {
            let mut next: Vec<Tree> = current.iter().flat_map(Tree::grow).collect();
            next.sort();
            next.dedup();
            all.extend(next.iter().cloned());
            current = next;
        }
        all
    }

    /// Largest order up to 6 whose conditions all hold for weights `b` (θ-scaled for
    /// dense output: `bᵀΦ(t) = θ^|t| / γ(t)`).
    fn satisfied_order(tab: &ButcherTableau, b: &[f64], theta: f64) -> usize {
        let a = |i: usize, j: usize| tab.a(i, j);
        let mut order = 0;
        for p in 1..=6 {
            let ok = trees_up_to(p).iter().filter(|t| t.order() == p).all(|t| {
                let phi = t.weights(tab, &a);
                let lhs: f64 = b.iter().zip(&phi).map(|(b, p)| b * p).sum();
                (lhs - theta.powi(p as i32) / t.density()).abs() < 1e-13
            });
            if !ok {
                break;
            }
            order = p;
        }
        order
    }

    #[test]
    fn tree_counts() {
        let counts: Vec<usize> = (1..=5)
            .map(|p| trees_up_to(p).iter().filter(|t| t.order() == p).count())
            .collect();
        assert_eq!(counts, [1, 1, 2, 4, 9]);
    }

    #[test]
    fn every_tableau_has_its_stated_orders() {
        for tab in ALL {
            let s = tab.stages();
            assert!(tab.a.len() == s && tab.c.len() == s, "{}", tab.name);
            for i in 0..s {
                let row: f64 = (0..s).map(|j| tab.a(i, j)).sum();
                assert!((row - tab.c[i]).abs() < 1e-14, "{}: row sum {i}", tab.name);
            }
            assert_eq!(
                satisfied_order(tab, tab.b, 1.0),
                tab.order as usize,
                "{}",
                tab.name
            );
            if let (Some(bh), Some(p)) = (tab.b_hat, tab.embedded_order) {
                assert_eq!(
                    satisfied_order(tab, bh, 1.0),
                    p as usize,
                    "{} embedded",
                    tab.name
                );
            }
        }
    }

    #[test]
    fn sdirk4_is_stiffly_accurate_and_l_stable() {
        let s = SDIRK4.stages();
        assert_eq!(SDIRK4.a[s - 1], SDIRK4.b);
        // Stiffly accurate with non-singular A ⇒ R(∞) = 0; check R(z) → 0 numerically:
        // R(z) = 1 + z bᵀ (I − zA)⁻¹ 𝟙.
        let z = -1e8;
        let a = nalgebra::DMatrix::from_fn(s, s, |i, j| SDIRK4.a(i, j));
        let m = nalgebra::DMatrix::identity(s, s) - a * z;
        let x = m
            .lu()
            .solve(&nalgebra::DVector::from_element(s, 1.0))
            .unwrap();
        let r = 1.0 + z * nalgebra::DVector::from_column_slice(SDIRK4.b).dot(&x);
        assert!(r.abs() < 1e-6);
        for i in 0..s {
            assert_eq!(SDIRK4.a(i, i), 0.25);
        }
    }

    /// Why SDIRK4 needs many steps on Prothero–Robinson problems `y' = λ(y − φ(t))`
    /// with `hλ ≪ −1`. Writing the estimate as `dᵀZ` with `Z = hAK` the stage
    /// increments and `dᵀ = (b − b̂)ᵀA⁻¹`: in the stiff limit `Z_i ≈ φ(t₀ + c_i h) − φ(t₀)`,
    /// so the estimate is `dᵀc h φ' + dᵀc² h²φ''/2 + …`. Here `dᵀc = 0` but `dᵀc² = −1/3`,
    /// and the order-3 conditions on `e = b − b̂` have rank 4 on these 5 stages, so every
    /// order-3 embedded formula gives a multiple of this same `d`: the O(h²) stiff-limit
    /// estimate (divided by `1 − hγλ` by the filter) belongs to the method, not to the code.
    #[test]
    fn sdirk4_error_estimate_is_unique_and_order_reduced_when_stiff() {
        use nalgebra::{DMatrix, DVector};
        let s = SDIRK4.stages();
        let a = DMatrix::from_fn(s, s, |i, j| SDIRK4.a(i, j));
        let c = DVector::from_column_slice(SDIRK4.c);
        let c2 = c.component_mul(&c);
        let e = DVector::from_vec(SDIRK4.error_weights());
        let d = a.transpose().lu().solve(&e).unwrap();
        assert!(d.dot(&c).abs() < 1e-13);
        assert!((d.dot(&c2) + 1.0 / 3.0).abs() < 1e-13, "{}", d.dot(&c2));
        // Rows: eᵀ𝟙 = 0, eᵀc = 0, eᵀc² = 0, eᵀAc = 0.
        let ac = &a * &c;
        let conditions = DMatrix::from_fn(4, s, |k, j| match k {
            0 => 1.0,
            1 => c[j],
            2 => c2[j],
            _ => ac[j],
        });
        assert_eq!(conditions.rank(1e-12), 4);
        assert!((&conditions * &e).norm() < 1e-13);
    }

    /// The continuous extension has order 4 for every θ: its weights `b_i(θ)`, read off
    /// by linearity, satisfy the θ-scaled conditions up to order 4.
    #[test]
    fn dopri5_dense_output_has_order_four() {
        for theta in [0.1, 0.37, 0.5, 0.8, 1.0] {
            let b: Vec<f64> = (0..7)
                .map(|i| {
                    // One-dimensional step with y0 = 0, h = 1 and k = e_i.
                    let y1 = DOPRI5.b[i];
                    let f0 = f64::from(i == 0);
                    let f1 = f64::from(i == 6);
                    dopri5_dense(theta, 1.0, 0.0, y1, f0, f1, DOPRI5_DENSE[i])
                })
                .collect();
            assert!(satisfied_order(&DOPRI5, &b, theta) >= 4, "θ = {theta}");
        }
    }
}
