"""MuJoCo on the report's contact scenes (theory §8), with its default contact
parameters and with its stiffest, beside the closed forms.

Scenes, each the same physics as the bundled Rust scenes (`SlidingBox`, `SpinningBall`):

- a 1 kg box, 0.4 m x 0.2 m (and 0.1 m deep), on a plane tilted by 0.3 rad with
  friction 0.5 (below its friction angle, 0.4636 rad): how far it creeps in 10 s;
- the same box launched at 2 m/s on level ground: when and where it stops;
- a 1 kg ball of radius 0.1 m dropped from 0.2 m with restitution 0.5 asked for: the
  restitution that comes out (rebound over impact speed at the first bounce);
- the ball at rest on the ground: how deep it sits and how much its height jitters;
- each with the run time per simulated second.

"Default": MuJoCo's defaults (timestep 2 ms, solref 0.02 1, solimp 0.9 0.95 0.001,
pyramidal cones). "Stiff": timestep 0.2 ms, solref 0.0004 1 (twice the timestep, the
stiffest MuJoCo recommends), solimp 0.99 0.999 0.0001, elliptic cones, impratio 10.
Restitution is asked for through solref's negative form (-stiffness, -damping), with
the damping that gives e for the linear spring-damper MuJoCo's contact is.

Writes TSV rows: scene, setting, quantity, value, closed form, seconds per simulated
second; then the traces the report plots beside ours, as rows `trace`, trace name,
setting, time, value (recorded in separate, untimed runs): the box's displacement on
the incline, the launched box's position, the dropped ball's height above the ground.
"""

import math
import sys
import time

import mujoco
import numpy as np

G = 9.81


def settings():
    return {
        "default": dict(timestep=0.002, solref="0.02 1", solimp="0.9 0.95 0.001", cone="pyramidal", impratio=1),
        "stiff": dict(timestep=0.0002, solref="0.0004 1", solimp="0.99 0.999 0.0001", cone="elliptic", impratio=10),
    }


def box_xml(s, phi, mu):
    c, sn = math.cos(phi), math.sin(phi)
    # The box resting on the tilted plane, its bottom face on it.
    x, z = -0.1 * sn, 0.1 * c
    return f"""
<mujoco>
  <option timestep="{s['timestep']}" cone="{s['cone']}" impratio="{s['impratio']}" gravity="0 0 -{G}"/>
  <worldbody>
    <body euler="0 {-phi} 0">
      <geom type="plane" size="50 50 0.1" friction="{mu} 0.005 0.0001" solref="{s['solref']}" solimp="{s['solimp']}"/>
    </body>
    <body name="box" pos="{x} 0 {z}" euler="0 {-phi} 0">
      <freejoint/>
      <geom type="box" size="0.2 0.05 0.1" mass="1" friction="{mu} 0.005 0.0001" solref="{s['solref']}" solimp="{s['solimp']}"/>
    </body>
  </worldbody>
</mujoco>"""


def ball_xml(s, solref):
    return f"""
<mujoco>
  <option timestep="{s['timestep']}" cone="{s['cone']}" impratio="{s['impratio']}" gravity="0 0 -{G}"/>
  <worldbody>
    <geom type="plane" size="50 50 0.1" solref="{solref}" solimp="{s['solimp']}"/>
    <body name="ball" pos="0 0 0.3">
      <freejoint/>
      <geom type="sphere" size="0.1" mass="1" solref="{solref}" solimp="{s['solimp']}"/>
    </body>
  </worldbody>
</mujoco>"""


def run(model, data, seconds, each=None):
    steps = int(round(seconds / model.opt.timestep))
    start = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(model, data)
        if each is not None:
            each(data)
    return (time.perf_counter() - start) / seconds


def trace(model, data, seconds, every, value):
    """(t, value(data)) every `every` seconds of a run of `seconds`."""
    steps = int(round(seconds / model.opt.timestep))
    stride = max(1, int(round(every / model.opt.timestep)))
    out = [(data.time, value(data))]
    for i in range(steps):
        mujoco.mj_step(model, data)
        if (i + 1) % stride == 0:
            out.append((data.time, value(data)))
    return out


def traces(name, s):
    rows = []
    m = mujoco.MjModel.from_xml_string(box_xml(s, 0.3, 0.5))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    p0 = d.qpos[:3].copy()
    for t, x in trace(m, d, 10.0, 0.02, lambda data: float(np.linalg.norm(data.qpos[:3] - p0))):
        rows.append(("incline", name, t, x))
    m = mujoco.MjModel.from_xml_string(box_xml(s, 0.0, 0.5))
    d = mujoco.MjData(m)
    d.qvel[0] = 2.0
    mujoco.mj_forward(m, d)
    x0 = d.qpos[0]
    for t, x in trace(m, d, 1.0, 0.005, lambda data: float(data.qpos[0] - x0)):
        rows.append(("box", name, t, x))
    e = 0.5
    zeta = -math.log(e) / math.sqrt(math.pi**2 + math.log(e) ** 2)
    k = (2 * math.pi / (10 * s["timestep"])) ** 2
    m = mujoco.MjModel.from_xml_string(ball_xml(s, f"{-k} {-2 * zeta * math.sqrt(k)}"))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    for t, z in trace(m, d, 1.5, 0.002, lambda data: float(data.qpos[2] - 0.1)):
        rows.append(("ball", name, t, z))
    return rows


def main(out):
    rows = []
    for name, s in settings().items():
        # Creep below the friction angle over 10 s.
        phi, mu = 0.3, 0.5
        m = mujoco.MjModel.from_xml_string(box_xml(s, phi, mu))
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        p0 = d.qpos[:3].copy()
        cost = run(m, d, 10.0)
        creep = float(np.linalg.norm(d.qpos[:3] - p0))
        rows.append(("incline below its friction angle", name, "displacement in 10 s [m]", creep, 0.0, cost))
        # Launched at 2 m/s on level ground.
        m = mujoco.MjModel.from_xml_string(box_xml(s, 0.0, mu))
        d = mujoco.MjData(m)
        d.qvel[0] = 2.0
        mujoco.mj_forward(m, d)
        x0 = d.qpos[0]
        stopped = [None]

        def watch(data):
            if stopped[0] is None and data.qvel[0] <= 1e-3:
                stopped[0] = data.time

        cost = run(m, d, 1.0, watch)
        t_stop, dist = 2.0 / (mu * G), 2.0 * 2.0 / (2 * mu * G)
        rows.append(("box sliding to rest", name, "stop time [s]", stopped[0] if stopped[0] is not None else float("nan"), t_stop, cost))
        rows.append(("box sliding to rest", name, "distance [m]", float(d.qpos[0] - x0), dist, cost))
        # A ball asking for e = 0.5 (negative solref: stiffness, damping of the contact's
        # spring-damper; damping 2 ζ sqrt(k) with ζ for e = exp(-ζ π / sqrt(1 - ζ²))).
        e = 0.5
        zeta = -math.log(e) / math.sqrt(math.pi**2 + math.log(e) ** 2)
        k = (2 * math.pi / (10 * s["timestep"])) ** 2
        solref = f"{-k} {-2 * zeta * math.sqrt(k)}"
        m = mujoco.MjModel.from_xml_string(ball_xml(s, solref))
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        vz = []

        def record(data):
            vz.append(data.qvel[2])

        cost = run(m, d, 1.0, record)
        v = np.array(vz)
        # The first impact: the fall's last downward speed and the first upward speed after.
        first_up = int(np.argmax(v > 0))
        v_in = -v[:first_up].min() if first_up > 0 else float("nan")
        v_out = v[first_up : first_up + int(0.1 / m.opt.timestep)].max() if first_up > 0 else float("nan")
        rows.append(("dropped ball", name, "restitution (e = 0.5 asked)", float(v_out / v_in), e, cost))
        # At rest: depth and jitter over the last second of 3.
        m = mujoco.MjModel.from_xml_string(ball_xml(s, s["solref"]))
        d = mujoco.MjData(m)
        d.qpos[2] = 0.1
        mujoco.mj_forward(m, d)
        run(m, d, 2.0)
        z = []
        cost = run(m, d, 1.0, lambda data: z.append(data.qpos[2]))
        z = np.array(z)
        rows.append(("ball at rest", name, "penetration [m]", float(0.1 - z.mean()), 0.0, cost))
        rows.append(("ball at rest", name, "height jitter (std) [m]", float(z.std()), 0.0, cost))
    traced = [r for name, s in settings().items() for r in traces(name, s)]
    with open(out, "w") as f:
        f.write(f"# MuJoCo {mujoco.__version__}\n")
        for r in rows:
            f.write("\t".join(str(x) for x in r) + "\n")
        for r in traced:
            f.write("\t".join(["trace"] + [str(x) for x in r]) + "\n")


if __name__ == "__main__":
    main(sys.argv[1])
