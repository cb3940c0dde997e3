use filippov::Mechanism;

// Paths are relative to the crate's Cargo.toml; trybuild compiles this file in its own
// crate under target/tests/trybuild/filippov-macros, four levels below the repository.

// A <mimic> joint, named, with the way out.
#[derive(Mechanism)]
#[mechanism(urdf = "../../../../macros/tests/ui/urdf/mimic.urdf")]
struct Gripper;

// Unknown `limits` and a `lock` naming no joint of the file.
#[derive(Mechanism)]
#[mechanism(urdf = "../../../../macros/tests/ui/urdf/mimic.urdf", lock = [finger_right, thumb], limits = walls)]
struct Locked;

// URDF options without a file, and a path that is not a string.
#[derive(Mechanism)]
#[mechanism(joint_friction = true, base = free)]
#[body(link, mass = 1.0, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(j: revolute(z), parent = world, child = link)]
struct NoFile;

#[derive(Mechanism)]
#[mechanism(urdf = robots::panda)]
struct NotAString;

// Bindings: an element the file does not have, a property that cannot be bound, a
// limit bound without stops, a locked joint.
#[derive(Mechanism)]
#[mechanism(urdf = "../../../../macros/tests/ui/urdf/mimic.urdf", lock = [finger_right])]
#[urdf_param(thumb.mass = m, left.colour = m, finger_left.upper = m, finger_right.damping = m)]
struct Bound { m: f64 }

// A binding without a file.
#[derive(Mechanism)]
#[urdf_param(link.mass = m)]
#[body(link, mass = m, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(j: revolute(z), parent = world, child = link)]
struct NotUrdf { m: f64 }

// Inertial data no real body has: each error names the link.
#[derive(Mechanism)]
#[mechanism(urdf = "../../../../macros/tests/ui/urdf/negative_mass.urdf")]
struct NegativeMass;

#[derive(Mechanism)]
#[mechanism(urdf = "../../../../macros/tests/ui/urdf/unphysical_inertia.urdf")]
struct UnphysicalInertia;

// A movable joint whose axis has no direction: named as the file names it, with the
// URDF to write, and nothing after it.
#[derive(Mechanism)]
#[mechanism(urdf = "../../../../macros/tests/ui/urdf/zero_axis.urdf")]
struct ZeroAxis;

fn main() {}
