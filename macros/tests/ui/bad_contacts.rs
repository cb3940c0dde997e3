use filippov::Mechanism;

// Each contact has one mistake, each reported once at its tokens.
#[derive(Mechanism)]
#[body(block, mass = m, inertia = sphere(m, 0.1))]
#[joint(slide: prismatic(x), parent = world, child = block)]
#[body(lid, mass = m, inertia = sphere(m, 0.1))]
#[joint(hinge: revolute(z), parent = block, child = lid)]
#[contact(shapeless, body = block, normal = y)]
#[contact(cube: cube(0.1), body = block, normal = y)]
#[contact(ghost: point, body = floor, normal = y)]
#[contact(anchored: point, body = world, normal = y)]
#[contact(self_touch: point, body = lid, plane = lid, normal = y)]
#[contact(tilted: point, body = block, normal = [0.0, 0.6, 0.8])]
#[contact(flat: point, body = block)]
#[contact(slippery: point, body = block, normal = y, mu = -0.2)]
#[contact(superball: sphere(0.1), body = block, normal = y, restitution = 1.5)]
#[contact(hollow: sphere(-0.1), body = block, normal = y)]
#[contact(slide: point, body = block, normal = y)]
#[contact(typo: point, body = block, normal = y, muu = 0.3)]
#[contact(grippy: point, body = block, normal = y, mu = 0.5, mu_static = 0.3)]
struct Box2 {
    m: f64,
}

fn main() {}
