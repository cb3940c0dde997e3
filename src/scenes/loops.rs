use filippov::Mechanism;

/// A Grashof crank-rocker four-bar in the x–y plane under gravity along −y, without
/// losses: the crank (`a`) turns about the origin, the coupler (`b`) hangs from its end,
/// the rocker (`c`) turns about `(d, 0)`, and a loop joint pins the coupler's end to the
/// rocker's (theory §7). The tree's coordinates are the crank angle, the coupler's angle
/// relative to the crank and the rocker's angle; the loop joint adds two constraints.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = [energy], gravity = [0.0, -g, 0.0])]
#[body(crank, mass = ma, com = [a / 2.0, 0.0, 0.0], inertia = rod(ma, a))]
#[joint(crank_pivot: revolute(z), parent = world, child = crank)]
#[body(coupler, mass = mb, com = [b / 2.0, 0.0, 0.0], inertia = rod(mb, b))]
#[joint(crank_pin: revolute(z), parent = crank, child = coupler, origin = [a, 0.0, 0.0])]
#[body(rocker, mass = mc, com = [c / 2.0, 0.0, 0.0], inertia = rod(mc, c))]
#[joint(rocker_pivot: revolute(z), parent = world, child = rocker, origin = [d, 0.0, 0.0])]
#[loop_joint(rocker_pin: revolute(z), parent = coupler, child = rocker, origin = [b, 0.0, 0.0], child_origin = [c, 0.0, 0.0])]
pub struct FourBar {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
    pub ma: f64,
    pub mb: f64,
    pub mc: f64,
    pub g: f64,
}

impl Default for FourBar {
    /// A crank-rocker: shortest link the crank, `a + b ≤ c + d` (Grashof).
    fn default() -> Self {
        FourBar {
            a: 0.3,
            b: 1.1,
            c: 0.8,
            d: 1.0,
            ma: 1.0,
            mb: 1.5,
            mc: 1.2,
            g: 9.81,
        }
    }
}

/// A slider-crank in the x–y plane pressing against a stop: the crank (`r`) turns about
/// the origin, driven through the input; the connecting rod (`l`) hangs from its end;
/// the slider runs along x on a prismatic joint with Coulomb friction `fc` and a rigid
/// stop at `s_max` (restitution `e`); a loop joint pins the rod's end to the slider (two
/// constraints).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = [energy], gravity = [0.0, -g, 0.0], inputs = [crank])]
#[body(crank_arm, mass = mc, com = [r / 2.0, 0.0, 0.0], inertia = rod(mc, r))]
#[joint(crank: revolute(z), parent = world, child = crank_arm)]
#[body(rod, mass = mr, com = [l / 2.0, 0.0, 0.0], inertia = rod(mr, l))]
#[joint(crank_pin: revolute(z), parent = crank_arm, child = rod, origin = [r, 0.0, 0.0])]
#[body(slider, mass = ms, com = [0.0, 0.0, 0.0], inertia = sphere(ms, 0.02))]
#[joint(stroke: prismatic(x), parent = world, child = slider)]
#[loop_joint(wrist_pin: revolute(z), parent = rod, child = slider, origin = [l, 0.0, 0.0])]
#[friction(stroke, f_crit = fc)]
#[stop(stroke, max = s_max, restitution = e)]
pub struct SliderCrank {
    pub r: f64,
    pub l: f64,
    pub mc: f64,
    pub mr: f64,
    pub ms: f64,
    pub fc: f64,
    pub s_max: f64,
    pub e: f64,
    pub g: f64,
}

impl Default for SliderCrank {
    /// Stroke `l − r … l + r = 0.25 … 0.45`, the stop at 0.43 (elastic), friction 3 N.
    fn default() -> Self {
        SliderCrank {
            r: 0.1,
            l: 0.35,
            mc: 0.5,
            mr: 0.4,
            ms: 1.0,
            fc: 3.0,
            s_max: 0.43,
            e: 1.0,
            g: 9.81,
        }
    }
}

/// Andrews' squeezing mechanism, the seven-body index-3 benchmark of the IVP test set
/// (Mazzia & Magherini; Hairer & Wanner, *Solving ODEs II*, §VII.7), in the plane: a
/// crank (β, driven by the torque `mom` through the simulation's input) and a link
/// (Θ, relative to the crank) whose end E is pinned to three more chains — a lever (γ)
/// pulled by a spring from the fixed point C, and two two-body chains from A (δ then Φ
/// relative to it; ε then Ω relative to it). The tree's coordinates are the test set's
/// seven angles, in the tree's order `[β, Θ, γ, δ, Φ, ε, Ω]` ([`Self::TEST_SET_ORDER`]
/// maps them to the test set's `(β, Θ, γ, Φ, δ, Ω, ε)`); three revolute loop joints at
/// E give the test set's six constraints (with the opposite sign: a loop joint's rows
/// are the child's point minus the parent's). No gravity. Where the test set leaves a
/// centre of mass's direction free (only its distance enters the equations), it is
/// placed as in the pymbs model of the problem.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = [energy], inputs = [beta])]
#[body(crank, mass = m1, com = [ra, 0.0, 0.0], inertia = diag(i1, i1, i1))]
#[joint(beta: revolute(z), parent = world, child = crank)]
#[body(link, mass = m2, com = [-da, 0.0, 0.0], inertia = diag(i2, i2, i2))]
#[joint(theta: revolute(z), parent = crank, child = link, origin = [rr, 0.0, 0.0])]
#[body(lever, mass = m3, com = [sb, -sa, 0.0], inertia = diag(i3, i3, i3))]
#[joint(gamma: revolute(z), parent = world, child = lever, origin = [xb, yb, 0.0])]
#[body(arm_a, mass = m5, com = [ta, tb, 0.0], inertia = diag(i5, i5, i5))]
#[joint(delta: revolute(z), parent = world, child = arm_a, origin = [xa, ya, 0.0])]
#[body(rod_a, mass = m4, com = [0.0, ea - e, 0.0], inertia = diag(i4, i4, i4))]
#[joint(phi: revolute(z), parent = arm_a, child = rod_a, origin = [zt, 0.0, 0.0])]
#[body(arm_b, mass = m7, com = [-ua, -ub, 0.0], inertia = diag(i7, i7, i7))]
#[joint(epsilon: revolute(z), parent = world, child = arm_b, origin = [xa, ya, 0.0])]
#[body(rod_b, mass = m6, com = [zf - fa, 0.0, 0.0], inertia = diag(i6, i6, i6))]
#[joint(omega: revolute(z), parent = arm_b, child = rod_b, origin = [0.0, -u, 0.0])]
#[loop_joint(e_lever: revolute(z), parent = link, child = lever, origin = [-d, 0.0, 0.0], child_origin = [0.0, -ss, 0.0])]
#[loop_joint(e_rod_a: revolute(z), parent = link, child = rod_a, origin = [-d, 0.0, 0.0], child_origin = [0.0, -e, 0.0])]
#[loop_joint(e_rod_b: revolute(z), parent = link, child = rod_b, origin = [-d, 0.0, 0.0], child_origin = [zf, 0.0, 0.0])]
#[spring(squeeze: between(world, lever), k = c0, rest = l0, from = [xc, yc, 0.0], to = [sd, -sc, 0.0])]
pub struct AndrewsSqueezer {
    pub m1: f64,
    pub m2: f64,
    pub m3: f64,
    pub m4: f64,
    pub m5: f64,
    pub m6: f64,
    pub m7: f64,
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
    pub i4: f64,
    pub i5: f64,
    pub i6: f64,
    pub i7: f64,
    pub xa: f64,
    pub ya: f64,
    pub xb: f64,
    pub yb: f64,
    pub xc: f64,
    pub yc: f64,
    pub c0: f64,
    pub l0: f64,
    pub d: f64,
    pub da: f64,
    pub e: f64,
    pub ea: f64,
    pub rr: f64,
    pub ra: f64,
    pub ss: f64,
    pub sa: f64,
    pub sb: f64,
    pub sc: f64,
    pub sd: f64,
    pub ta: f64,
    pub tb: f64,
    pub u: f64,
    pub ua: f64,
    pub ub: f64,
    pub zf: f64,
    pub zt: f64,
    pub fa: f64,
    /// The driving torque on β (applied through the input, see [`Self::torque`]).
    pub mom: f64,
}

impl Default for AndrewsSqueezer {
    /// The test set's parameters.
    fn default() -> Self {
        AndrewsSqueezer {
            m1: 0.04325,
            m2: 0.00365,
            m3: 0.02373,
            m4: 0.00706,
            m5: 0.07050,
            m6: 0.00706,
            m7: 0.05498,
            i1: 2.194e-6,
            i2: 4.410e-7,
            i3: 5.255e-6,
            i4: 5.667e-7,
            i5: 1.169e-5,
            i6: 5.667e-7,
            i7: 1.912e-5,
            xa: -0.06934,
            ya: -0.00227,
            xb: -0.03635,
            yb: 0.03273,
            xc: 0.014,
            yc: 0.072,
            c0: 4530.0,
            l0: 0.07785,
            d: 0.028,
            da: 0.0115,
            e: 0.02,
            ea: 0.01421,
            rr: 0.007,
            ra: 0.00092,
            ss: 0.035,
            sa: 0.01874,
            sb: 0.01043,
            sc: 0.018,
            sd: 0.02,
            ta: 0.02308,
            tb: 0.00916,
            u: 0.04,
            ua: 0.01228,
            ub: 0.00449,
            zf: 0.02,
            zt: 0.04,
            fa: 0.01421,
            mom: 0.033,
        }
    }
}

impl AndrewsSqueezer {
    /// Where each of the test set's angles `(β, Θ, γ, Φ, δ, Ω, ε)` is in the tree's
    /// coordinates `[β, Θ, γ, δ, Φ, ε, Ω]`.
    pub const TEST_SET_ORDER: [usize; 7] = [0, 1, 2, 4, 3, 6, 5];

    /// The input forces: the torque `mom` on β.
    pub fn torque(&self) -> filippov::nalgebra::SVector<f64, 7> {
        Self::input_forces(&filippov::nalgebra::SVector::from([self.mom]))
    }

    /// The test set's consistent initial positions at t = 0 (velocities zero), in the
    /// tree's coordinates.
    pub fn initial_positions() -> filippov::nalgebra::SVector<f64, 7> {
        let test_set = [
            -0.0617138900142764496358948458001,
            0.0,
            0.455279819163070380255912382449,
            0.222668390165885884674473185609,
            0.487364979543842550225598953530,
            -0.222668390165885884674473185609,
            1.23054744454982119249735015568,
        ];
        let mut q = filippov::nalgebra::SVector::zeros();
        for (k, &i) in Self::TEST_SET_ORDER.iter().enumerate() {
            q[i] = test_set[k];
        }
        q
    }
}

/// A Delta-style parallel robot (three closed loops), under gravity along −z: three legs
/// at 120° around the base, each an upper arm on a revolute joint about the base's
/// tangent and a forearm on a universal joint (two revolute joints through a massless
/// elbow), whose end is held to the moving platform by a ball (spherical loop joint);
/// the platform only translates (three prismatic joints through two massless carriages,
/// as a Delta's parallelograms keep it level). Twelve tree coordinates, nine constraint
/// rows, three degrees of freedom.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = [energy], gravity = [0.0, 0.0, -g], inputs = [hip_1, hip_2, hip_3])]
#[body(carriage_x, mass = 0.0)]
#[joint(platform_x: prismatic(x), parent = world, child = carriage_x, origin = [0.0, 0.0, -h])]
#[body(carriage_y, mass = 0.0)]
#[joint(platform_y: prismatic(y), parent = carriage_x, child = carriage_y)]
#[body(platform, mass = mp, com = [0.0, 0.0, 0.0], inertia = cylinder(mp, rp, 0.01))]
#[joint(platform_z: prismatic(z), parent = carriage_y, child = platform)]
#[body(arm_1, mass = ma, com = [la / 2.0, 0.0, 0.0], inertia = rod(ma, la))]
#[joint(hip_1: revolute(y), parent = world, child = arm_1, origin = [rb, 0.0, 0.0])]
#[body(elbow_1, mass = 0.0)]
#[joint(elbow_1a: revolute(y), parent = arm_1, child = elbow_1, origin = [la, 0.0, 0.0])]
#[body(forearm_1, mass = mf, com = [lf / 2.0, 0.0, 0.0], inertia = rod(mf, lf))]
#[joint(elbow_1b: revolute(z), parent = elbow_1, child = forearm_1)]
#[body(arm_2, mass = ma, com = [la / 2.0, 0.0, 0.0], inertia = rod(ma, la))]
#[joint(hip_2: revolute(y), parent = world, child = arm_2, origin = [rb * cos(2.0 * PI / 3.0), rb * sin(2.0 * PI / 3.0), 0.0], rpy = [0.0, 0.0, 2.0 * PI / 3.0])]
#[body(elbow_2, mass = 0.0)]
#[joint(elbow_2a: revolute(y), parent = arm_2, child = elbow_2, origin = [la, 0.0, 0.0])]
#[body(forearm_2, mass = mf, com = [lf / 2.0, 0.0, 0.0], inertia = rod(mf, lf))]
#[joint(elbow_2b: revolute(z), parent = elbow_2, child = forearm_2)]
#[body(arm_3, mass = ma, com = [la / 2.0, 0.0, 0.0], inertia = rod(ma, la))]
#[joint(hip_3: revolute(y), parent = world, child = arm_3, origin = [rb * cos(4.0 * PI / 3.0), rb * sin(4.0 * PI / 3.0), 0.0], rpy = [0.0, 0.0, 4.0 * PI / 3.0])]
#[body(elbow_3, mass = 0.0)]
#[joint(elbow_3a: revolute(y), parent = arm_3, child = elbow_3, origin = [la, 0.0, 0.0])]
#[body(forearm_3, mass = mf, com = [lf / 2.0, 0.0, 0.0], inertia = rod(mf, lf))]
#[joint(elbow_3b: revolute(z), parent = elbow_3, child = forearm_3)]
#[loop_joint(ball_1: spherical, parent = platform, child = forearm_1, origin = [rp, 0.0, 0.0], child_origin = [lf, 0.0, 0.0])]
#[loop_joint(ball_2: spherical, parent = platform, child = forearm_2, origin = [rp * cos(2.0 * PI / 3.0), rp * sin(2.0 * PI / 3.0), 0.0], child_origin = [lf, 0.0, 0.0])]
#[loop_joint(ball_3: spherical, parent = platform, child = forearm_3, origin = [rp * cos(4.0 * PI / 3.0), rp * sin(4.0 * PI / 3.0), 0.0], child_origin = [lf, 0.0, 0.0])]
pub struct Delta {
    /// Base radius (hip joints), platform radius (balls).
    pub rb: f64,
    pub rp: f64,
    /// Upper arm and forearm lengths.
    pub la: f64,
    pub lf: f64,
    pub ma: f64,
    pub mf: f64,
    pub mp: f64,
    /// Where the platform's carriage starts below the base.
    pub h: f64,
    pub g: f64,
}

impl Default for Delta {
    fn default() -> Self {
        Delta {
            rb: 0.2,
            rp: 0.05,
            la: 0.25,
            lf: 0.5,
            ma: 0.3,
            mf: 0.1,
            mp: 0.5,
            h: 0.4,
            g: 9.81,
        }
    }
}
