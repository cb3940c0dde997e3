"""Build a pinocchio.Model from filippov's JSON model (runtime/src/numeric/model.rs, Model::to_json).

Convention (URDF-like): link frame = parent · Trans(origin_xyz) · Rot(rpy) · joint motion(q),
Rot(rpy) = Rz(yaw) Ry(pitch) Rx(roll); axis, com and inertia (about the com) in the link frame.
"""
import json

import numpy as np
import pinocchio as pin


def rpy_matrix(rpy):
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1.0]])
    ry = np.array([[cp, 0, sp], [0, 1.0, 0], [-sp, 0, cp]])
    rx = np.array([[1.0, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def joint_for(kind, axis):
    """(pinocchio joint model, short type name used by the C++ program)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    unit = [np.allclose(a, e) for e in np.eye(3)]
    if kind == "revolute":
        if unit[0]:
            return pin.JointModelRX(), "RX"
        if unit[1]:
            return pin.JointModelRY(), "RY"
        if unit[2]:
            return pin.JointModelRZ(), "RZ"
        return pin.JointModelRevoluteUnaligned(a), "RU"
    if kind == "prismatic":
        if unit[0]:
            return pin.JointModelPX(), "PX"
        if unit[1]:
            return pin.JointModelPY(), "PY"
        if unit[2]:
            return pin.JointModelPZ(), "PZ"
        return pin.JointModelPrismaticUnaligned(a), "PU"
    raise ValueError(f"unknown joint kind {kind!r}")


def load(path):
    """Returns (model, spec, info): spec is the flat joint list the C++ benchmark rebuilds."""
    with open(path) as f:
        j = json.load(f)
    links = j["links"]
    model = pin.Model()
    model.gravity = pin.Motion(np.array(j["gravity"], dtype=float), np.zeros(3))
    # For every link: the pinocchio joint it moves with, and the placement of the link
    # frame in that joint's frame (identity unless fixed joints sit in between).
    link_joint, link_in_joint = [], []
    spec = []
    coords = []
    for i, l in enumerate(links):
        if l["parent"] is not None and l["parent"] >= i:
            raise ValueError(f"link {i} listed before its parent")
        origin = pin.SE3(rpy_matrix(l["origin_rpy"]), np.array(l["origin_xyz"], dtype=float))
        if l["parent"] is None:
            pj, pplace = 0, pin.SE3.Identity()
        else:
            pj, pplace = link_joint[l["parent"]], link_in_joint[l["parent"]]
        placement = pplace * origin
        inertia = pin.Inertia(float(l["mass"]), np.array(l["com"], dtype=float), np.array(l["inertia"], dtype=float))
        if l["joint"] == "fixed":
            model.appendBodyToJoint(pj, inertia, placement)
            link_joint.append(pj)
            link_in_joint.append(placement)
            continue
        jm, tname = joint_for(l["joint"], l["axis"])
        jid = model.addJoint(pj, jm, placement, l["name"])
        model.appendBodyToJoint(jid, inertia, pin.SE3.Identity())
        link_joint.append(jid)
        link_in_joint.append(pin.SE3.Identity())
        spec.append((tname, pj, placement, np.array(l["axis"], dtype=float), jid))
        coords.append(l["coordinate"])
    # our coordinate order must be pinocchio's (joints added in link order)
    if coords != sorted(coords) or coords != list(range(len(coords))):
        raise ValueError(f"coordinate order {coords} differs from pinocchio's joint order")
    info = {"springs": j.get("springs", []), "dampers": j.get("dampers", []), "links": len(links)}
    return model, spec, info


# Pinocchio joint types the C++ benchmark rebuilds (pin_bench.cpp reads these codes).
FLAT_TYPES = {
    "JointModelRX": "RX", "JointModelRY": "RY", "JointModelRZ": "RZ",
    "JointModelRevoluteUnaligned": "RU", "JointModelPX": "PX", "JointModelPY": "PY",
    "JointModelPZ": "PZ", "JointModelPrismaticUnaligned": "PU", "JointModelFreeFlyer": "FF",
}


def write_model(model, path, q, v, tau):
    """Any Pinocchio model built from the joint types in FLAT_TYPES (e.g. from a URDF,
    reduced or with a free-flyer base), as plain text for the C++ benchmark: each joint's
    type, parent, placement, axis and the inertia of its (merged) body, then q, v, tau."""
    spec = []
    for jid in range(1, model.njoints):
        joint = model.joints[jid]
        code = FLAT_TYPES.get(joint.shortname())
        if code is None:
            raise ValueError(f"joint {model.names[jid]}: type {joint.shortname()} is not one pin_bench.cpp rebuilds")
        axis = np.asarray(getattr(joint.extract(), "axis", np.array([1.0, 0.0, 0.0])), float)
        spec.append((code, int(model.parents[jid]), model.jointPlacements[jid], axis, jid))
    write_flat(model, spec, path, q, v, tau)


def write_flat(model, spec, path, q, v, tau):
    """Plain-text model + state for the C++ benchmark (inertias already merged)."""
    lines = [f"{len(spec)}", " ".join(repr(float(x)) for x in model.gravity.linear)]
    for tname, parent, placement, axis, jid in spec:
        I = model.inertias[jid]
        vals = [tname, str(parent)]
        vals += [repr(float(x)) for x in placement.rotation.reshape(-1)]
        vals += [repr(float(x)) for x in placement.translation]
        vals += [repr(float(x)) for x in axis / np.linalg.norm(axis)]
        vals += [repr(float(I.mass))] + [repr(float(x)) for x in I.lever]
        vals += [repr(float(x)) for x in I.inertia.reshape(-1)]
        lines.append(" ".join(vals))
    for vec in (q, v, tau):
        lines.append(" ".join(repr(float(x)) for x in vec))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
