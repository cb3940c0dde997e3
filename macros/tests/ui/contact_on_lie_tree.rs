use filippov::Mechanism;

// Contacts on a tree with a free joint are refused (not yet supported), naming the joint.
#[derive(Mechanism)]
#[body(ball, mass = m, inertia = sphere(m, 0.1))]
#[joint(float: free, parent = world, child = ball)]
#[contact(bottom: sphere(0.1), body = ball, normal = z)]
struct Ball {
    m: f64,
}

fn main() {}
