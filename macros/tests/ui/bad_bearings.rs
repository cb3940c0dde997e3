use filippov::Mechanism;

// Each bearing has one mistake, each reported once at its tokens.
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(cart, mass = m)]
#[joint(rail: prismatic(x), parent = world, child = cart)]
#[body(arm, mass = m, com = [0.0, -0.5, 0.0])]
#[joint(pin: revolute(z), parent = cart, child = arm)]
#[body(hand, mass = m, com = [0.0, -0.3, 0.0])]
#[joint(wrist: revolute(z), parent = arm, child = hand)]
#[body(other, mass = m)]
#[joint(lift: prismatic(y), parent = world, child = other)]
#[body(last, mass = m)]
#[joint(turn: revolute(z), parent = other, child = last)]
#[friction(rail, mu = 0.2, radius = 0.01)]
#[friction(pin, mu = 0.2)]
#[friction(wrist, mu = -0.1, radius = 0.01)]
#[friction(lift, mu = 0.2, f_static = 1.0, f_kinetic = 0.5)]
#[friction(turn, mu = 0.2, radius = 0.0)]
struct Mistakes {
    m: f64,
}

// A contact pushes on the bodies the rail carries from outside them.
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(cart, mass = 1.0)]
#[joint(rail: prismatic(x), parent = world, child = cart)]
#[body(bob, mass = 1.0, com = [0.0, -0.5, 0.0])]
#[joint(swing: revolute(z), parent = cart, child = bob)]
#[friction(rail, mu = 0.2)]
#[contact(foot: point, body = bob, at = [0.0, -0.5, 0.0], normal = y)]
struct Pushed;

// Switching functions are written in (q, v, f) and cannot hold a bearing's limit.
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0], emit = [switching_functions])]
#[body(cart, mass = 1.0)]
#[joint(rail: prismatic(x), parent = world, child = cart)]
#[friction(rail, mu = 0.2)]
struct Switched;

fn main() {}
