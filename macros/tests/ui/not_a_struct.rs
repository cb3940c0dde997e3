use filippov::Mechanism;

#[derive(Mechanism)]
enum Pendulum { Light, Heavy }

fn main() {}
