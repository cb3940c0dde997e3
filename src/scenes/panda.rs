use filippov::Mechanism;

/// A 7-dof arm with the kinematics of the Franka Emika Panda (its public URDF) and the
/// inertial parameters identified by Gaz, Cognetti, Oliva, Robuffo Giordano and De Luca,
/// "Dynamic identification of the Franka Emika Panda robot with retrieval of feasible
/// parameters using penalty-based optimization", IEEE RA-L 4(4), 2019.
/// Inertias are about the centres of mass, in the link frames.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all, gravity = [0.0, 0.0, -g], inputs = [j1, j2, j3, j4, j5, j6, j7])]
#[body(link1, mass = 4.970684, com = [0.003875, 0.002081, -0.04762],
    inertia = [[0.70337, -0.000139, 0.006772], [-0.000139, 0.70661, 0.019169], [0.006772, 0.019169, 0.009117]])]
#[joint(j1: revolute(z), parent = world, child = link1, origin = [0.0, 0.0, 0.333])]
#[body(link2, mass = 0.646926, com = [-0.003141, -0.02872, 0.003495],
    inertia = [[0.007962, -0.003925, 0.010254], [-0.003925, 0.02811, 0.000704], [0.010254, 0.000704, 0.025995]])]
#[joint(j2: revolute(z), parent = link1, child = link2, rpy = [-PI / 2.0, 0.0, 0.0])]
#[body(link3, mass = 3.228604, com = [0.027518, 0.039252, -0.066502],
    inertia = [[0.037242, -0.004761, -0.011396], [-0.004761, 0.036155, -0.012805], [-0.011396, -0.012805, 0.01083]])]
#[joint(j3: revolute(z), parent = link2, child = link3, origin = [0.0, -0.316, 0.0], rpy = [PI / 2.0, 0.0, 0.0])]
#[body(link4, mass = 3.587895, com = [-0.05317, 0.104419, 0.027454],
    inertia = [[0.025853, 0.007796, -0.001332], [0.007796, 0.019552, 0.008641], [-0.001332, 0.008641, 0.028323]])]
#[joint(j4: revolute(z), parent = link3, child = link4, origin = [0.0825, 0.0, 0.0], rpy = [PI / 2.0, 0.0, 0.0])]
#[body(link5, mass = 1.225946, com = [-0.011953, 0.041065, -0.038437],
    inertia = [[0.035549, -0.002117, -0.004037], [-0.002117, 0.029474, 0.000229], [-0.004037, 0.000229, 0.008627]])]
#[joint(j5: revolute(z), parent = link4, child = link5, origin = [-0.0825, 0.384, 0.0], rpy = [-PI / 2.0, 0.0, 0.0])]
#[body(link6, mass = 1.666555, com = [0.060149, -0.014117, -0.010517],
    inertia = [[0.001964, 0.000109, -0.001158], [0.000109, 0.004354, 0.000341], [-0.001158, 0.000341, 0.005433]])]
#[joint(j6: revolute(z), parent = link5, child = link6, rpy = [PI / 2.0, 0.0, 0.0])]
#[body(link7, mass = 0.735522, com = [0.010517, -0.004252, 0.061597],
    inertia = [[0.012516, -0.000428, -0.001196], [-0.000428, 0.010027, -0.000741], [-0.001196, -0.000741, 0.004815]])]
#[joint(j7: revolute(z), parent = link6, child = link7, origin = [0.088, 0.0, 0.0], rpy = [PI / 2.0, 0.0, 0.0])]
pub struct Panda {
    pub g: f64,
}

impl Default for Panda {
    fn default() -> Self {
        Panda { g: 9.81 }
    }
}
