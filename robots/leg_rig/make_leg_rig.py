#!/usr/bin/env python3
"""Generates the leg rig's robot description: robots/leg_rig/leg_rig.urdf.

    python3 robots/leg_rig/make_leg_rig.py           # write the URDF, then check it
    python3 robots/leg_rig/make_leg_rig.py --check   # only check the file on disk (exit 1 on failure)

Python 3 standard library only; the output is deterministic (the same bytes every run).

A single leg on a vertical rail, as a hopping test rig is built: a stand (the root link,
welded to the world) with two vertical rails, a carriage ('body') on a passive
prismatic joint ('rail'), a hip pitch joint driven by a geared motor (kind rotary), a
thigh, a knee driven by a geared motor with a torsion spring (kind rotary_sea), a shank,
a passive ankle and a foot with a flat box sole. Every number is chosen; README.md says
why. Each link's mass, centre of mass and inertia are computed here from its parts
(boxes, cylinders, tubes of stated masses), and the same parts are its visuals, so what
is drawn is what is simulated.

Conventions: SI units; with every joint at 0 each link frame is parallel to the world
(x forward, y left, z up). The stand's origin is on the ground under the hip axis; the
rail coordinate is the height of the hip axis above the ground (m). Hip pitch negative
swings the thigh forward, knee positive flexes it (the foot goes back), the ankle is
free (no actuator, no effort): the foot hangs level in the air and sits flat on the
ground. The symmetric crouch hip = -a, knee = 2a, ankle = -a keeps the foot under the
hip and the sole flat.
"""

import argparse
import math
import os
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
URDF_PATH = os.path.join(HERE, "leg_rig.urdf")

# ----------------------------------------------------------------------------------
# Geometry (m)
# ----------------------------------------------------------------------------------
THIGH_M = 0.30          # hip axis to knee axis
SHANK_M = 0.30          # knee axis to ankle axis
SOLE_BOTTOM_M = 0.06    # below the ankle axis
SOLE = (0.16, 0.08, 0.02)   # the box sole (x long, y wide, z thick), centred under the ankle
RAIL_X = -0.12          # the rails' axis line, behind the hip (x), at y = +-RAIL_Y
RAIL_Y = 0.09
RAIL_R = 0.012
RAIL_TOP = 1.0          # the rails' height

# Joints: name -> (type, parent, child, origin xyz in parent, axis, (lower, upper), effort, velocity, damping)
#   rail: passive, no actuator; effort 0 (dmbd reads 0 as no limit; nothing drives it);
#         damping 5 N s/m: linear bearings and the cable (chosen).
#   hip, knee: effort = the gearbox's torque rating (actuators.yaml torque_limit_Nm, 60 N m);
#         velocity = the motor's no-load speed at 48 V / the gear ratio = 640 / 50 rad/s, rounded down.
#   ankle: passive pin, damping 0.02 N m s/rad (damps the hanging foot's swing).
JOINTS = [
    ("rail", "prismatic", "stand", "body", (0.0, 0.0, 0.0), (0, 0, 1), (0.25, 0.80), 0.0, 5.0, 5.0),
    ("hip", "revolute", "body", "thigh", (0.0, 0.0, 0.0), (0, 1, 0), (-1.5, 0.5), 60.0, 12.0, 0.0),
    ("knee", "revolute", "thigh", "shank", (0.0, 0.0, -THIGH_M), (0, 1, 0), (0.0, 2.4), 60.0, 12.0, 0.0),
    ("ankle", "revolute", "shank", "foot", (0.0, 0.0, -SHANK_M), (0, 1, 0), (-1.2, 0.6), 0.0, 20.0, 0.02),
]

# Parts per link: (name, shape, size, centre xyz, axis, mass kg, material, collision?)
#   shape box: size (x, y, z); cylinder: (radius, length); tube: (outer, inner radius, length)
#   axis: the cylinder's or tube's axis, 'x', 'y' or 'z'. mass 0: drawn only.
ROT_Y = "y"
PARTS = {
    "stand": [
        ("base plate", "box", (0.30, 0.40, 0.015), (-0.26, 0.0, 0.0075), "z", 14.0, "steel", False),
        ("left rail", "cylinder", (RAIL_R, RAIL_TOP), (RAIL_X, RAIL_Y, RAIL_TOP / 2), "z", 0.9, "steel", False),
        ("right rail", "cylinder", (RAIL_R, RAIL_TOP), (RAIL_X, -RAIL_Y, RAIL_TOP / 2), "z", 0.9, "steel", False),
        ("top beam", "box", (0.04, 0.24, 0.03), (RAIL_X, 0.0, RAIL_TOP + 0.015), "z", 0.8, "frame", False),
        ("rear post", "box", (0.04, 0.04, RAIL_TOP), (-0.38, 0.0, RAIL_TOP / 2 + 0.015), "z", 3.0, "frame", False),
        ("top brace", "box", (0.26, 0.04, 0.03), (-0.25, 0.0, RAIL_TOP + 0.015), "z", 0.6, "frame", False),
        ("bottom rail mount", "box", (0.05, 0.24, 0.03), (RAIL_X, 0.0, 0.03), "z", 1.0, "frame", False),
    ],
    "body": [
        ("carriage plate", "box", (0.02, 0.22, 0.18), (-0.09, 0.0, 0.0), "z", 1.0, "aluminium", False),
        ("bearing block upper left", "box", (0.04, 0.035, 0.04), (RAIL_X, RAIL_Y, 0.06), "z", 0.15, "frame", False),
        ("bearing block upper right", "box", (0.04, 0.035, 0.04), (RAIL_X, -RAIL_Y, 0.06), "z", 0.15, "frame", False),
        ("bearing block lower left", "box", (0.04, 0.035, 0.04), (RAIL_X, RAIL_Y, -0.06), "z", 0.15, "frame", False),
        ("bearing block lower right", "box", (0.04, 0.035, 0.04), (RAIL_X, -RAIL_Y, -0.06), "z", 0.15, "frame", False),
        ("hip bearing housing", "box", (0.08, 0.05, 0.09), (-0.04, 0.0, 0.0), "z", 0.6, "aluminium", False),
        ("hip drive (motor and gearbox)", "cylinder", (0.045, 0.075), (0.0, 0.0725, 0.0), ROT_Y, 1.4, "motor", False),
        ("ballast plate", "box", (0.10, 0.16, 0.016), (-0.05, 0.0, 0.098), "z", 2.0, "ballast", False),
        ("motor drivers", "box", (0.06, 0.10, 0.03), (-0.06, 0.0, -0.075), "z", 0.4, "electronics", False),
        # The carriage's collision: one box around the carriage.
        ("carriage envelope", "box", (0.16, 0.22, 0.22), (-0.05, 0.0, 0.01), "z", 0.0, None, True),
    ],
    "thigh": [
        ("thigh tube", "tube", (0.022, 0.019, THIGH_M - 0.04), (0.0, 0.0, -THIGH_M / 2), "z", 0.30, "aluminium", False),
        ("hip clamp", "box", (0.05, 0.05, 0.05), (0.0, 0.0, -0.01), "z", 0.12, "aluminium", False),
        ("knee clevis", "box", (0.05, 0.06, 0.05), (0.0, 0.0, -THIGH_M + 0.01), "z", 0.12, "aluminium", False),
        ("knee drive (motor and gearbox)", "cylinder", (0.045, 0.08), (0.0, -0.075, -THIGH_M), ROT_Y, 1.3, "motor", False),
        ("knee torsion spring", "cylinder", (0.035, 0.012), (0.0, -0.029, -THIGH_M), ROT_Y, 0.0, "spring", False),
        ("thigh collision", "cylinder", (0.022, THIGH_M - 0.06), (0.0, 0.0, -THIGH_M / 2), "z", 0.0, None, True),
    ],
    "shank": [
        ("shank tube", "tube", (0.018, 0.015, SHANK_M - 0.04), (0.0, 0.0, -SHANK_M / 2), "z", 0.24, "aluminium", False),
        ("knee hub", "cylinder", (0.025, 0.04), (0.0, 0.0, 0.0), ROT_Y, 0.10, "aluminium", False),
        ("ankle clevis", "box", (0.04, 0.05, 0.04), (0.0, 0.0, -SHANK_M + 0.01), "z", 0.08, "aluminium", False),
        ("shank collision", "cylinder", (0.018, SHANK_M - 0.06), (0.0, 0.0, -SHANK_M / 2), "z", 0.0, None, True),
    ],
    "foot": [
        ("ankle block", "box", (0.04, 0.03, 0.04), (0.0, 0.0, -0.02), "z", 0.08, "aluminium", False),
        ("sole plate", "box", (SOLE[0], SOLE[1], 0.01), (0.0, 0.0, -SOLE_BOTTOM_M + 0.015), "z", 0.30, "aluminium", False),
        ("rubber sole", "box", (SOLE[0], SOLE[1], 0.01), (0.0, 0.0, -SOLE_BOTTOM_M + 0.005), "z", 0.12, "rubber", False),
        ("sole", "box", SOLE, (0.0, 0.0, -SOLE_BOTTOM_M + SOLE[2] / 2), "z", 0.0, None, True),
    ],
}
LINKS = ["stand", "body", "thigh", "shank", "foot"]

MATERIALS = [  # name, rgba
    ("steel", (0.72, 0.73, 0.75, 1.0)),        # rails, base plate
    ("frame", (0.20, 0.21, 0.23, 1.0)),        # extrusions, bearing blocks
    ("aluminium", (0.80, 0.82, 0.85, 1.0)),    # carriage, tubes, clevises
    ("motor", (0.12, 0.14, 0.18, 1.0)),        # drives
    ("spring", (0.95, 0.47, 0.10, 1.0)),       # the knee's torsion spring
    ("ballast", (0.35, 0.30, 0.28, 1.0)),      # steel ballast plate
    ("electronics", (0.10, 0.35, 0.20, 1.0)),  # motor drivers
    ("rubber", (0.05, 0.05, 0.05, 1.0)),       # sole
]

# Checks (README): the moving mass in the brief's range; the crouch used by the scenario.
MOVING_MASS_RANGE_KG = (8.0, 15.0)
CROUCH_RAD = 0.5


# ----------------------------------------------------------------------------------
# Mass properties
# ----------------------------------------------------------------------------------


def axis_rotation(axis):
    """Rotation taking a part's z (its axis) to `axis`, as URDF rpy and as a matrix."""
    if axis == "z":
        return (0.0, 0.0, 0.0), ((1, 0, 0), (0, 1, 0), (0, 0, 1))
    if axis == "y":   # roll -pi/2: z -> +y
        return (-math.pi / 2, 0.0, 0.0), ((1, 0, 0), (0, 0, 1), (0, -1, 0))
    raise ValueError(axis)


def local_inertia(shape, size, m):
    """Principal moments about the part's centre, in its own frame (axis z)."""
    if shape == "box":
        a, b, c = size
        return (m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12)
    if shape == "cylinder":
        r, length = size
        t = m * (3 * r * r + length * length) / 12
        return (t, t, m * r * r / 2)
    if shape == "tube":
        ro, ri, length = size
        t = m * (3 * (ro * ro + ri * ri) + length * length) / 12
        return (t, t, m * (ro * ro + ri * ri) / 2)
    raise ValueError(shape)


def mass_properties(parts):
    """Mass, centre of mass and the inertia tensor about it (3x3 rows) of a link's parts."""
    mass = sum(p[5] for p in parts)
    com = tuple(sum(p[5] * p[3][i] for p in parts) / mass for i in range(3))
    inertia = [[0.0] * 3 for _ in range(3)]
    for _, shape, size, centre, axis, m, _, _ in parts:
        if m == 0:
            continue
        d = local_inertia(shape, size, m)
        _, rot = axis_rotation(axis)
        # R diag(d) R^T, then the parallel-axis term m (|r|^2 I - r r^T).
        r = tuple(centre[i] - com[i] for i in range(3))
        rr = sum(x * x for x in r)
        for i in range(3):
            for j in range(3):
                inertia[i][j] += sum(rot[i][k] * d[k] * rot[j][k] for k in range(3))
                inertia[i][j] += m * ((rr if i == j else 0.0) - r[i] * r[j])
    return mass, com, inertia


# ----------------------------------------------------------------------------------
# URDF text
# ----------------------------------------------------------------------------------


def num(x):
    """12 significant digits (and -0 as 0): the same text on every run."""
    return format(0.0 if x == 0 else x, ".12g")


def vec(v):
    return " ".join(num(x) for x in v)


def geometry(shape, size):
    if shape == "box":
        return f'<box size="{vec(size)}"/>'
    if shape == "cylinder":
        return f'<cylinder radius="{num(size[0])}" length="{num(size[1])}"/>'
    return f'<cylinder radius="{num(size[0])}" length="{num(size[2])}"/>'   # a tube is drawn as its outer cylinder


def link_xml(name):
    parts = PARTS[name]
    mass, com, inertia = mass_properties(parts)
    lines = [f'  <link name="{name}">',
             "    <inertial>",
             f'      <origin xyz="{vec(com)}"/>',
             f'      <mass value="{num(mass)}"/>',
             '      <inertia ixx="{}" ixy="{}" ixz="{}" iyy="{}" iyz="{}" izz="{}"/>'.format(
                 *(num(round(v, 9)) for v in (inertia[0][0], inertia[0][1], inertia[0][2], inertia[1][1], inertia[1][2],
                                              inertia[2][2]))),
             "    </inertial>"]
    for pname, shape, size, centre, axis, _, material, collision in parts:
        rpy, _ = axis_rotation(axis)
        origin = f'<origin xyz="{vec(centre)}"' + (f' rpy="{vec(rpy)}"/>' if any(rpy) else "/>")
        if collision:
            lines.append(f"    <collision><!-- {pname} -->{origin}<geometry>{geometry(shape, size)}</geometry></collision>")
        else:
            lines.append(f'    <visual><!-- {pname} -->{origin}<geometry>{geometry(shape, size)}</geometry>'
                         f'<material name="{material}"/></visual>')
    lines.append("  </link>")
    return "\n".join(lines)


def joint_xml(j):
    name, kind, parent, child, xyz, axis, (lo, hi), effort, velocity, damping = j
    return "\n".join([
        f'  <joint name="{name}" type="{kind}">',
        f'    <parent link="{parent}"/>',
        f'    <child link="{child}"/>',
        f'    <origin xyz="{vec(xyz)}"/>',
        f'    <axis xyz="{vec(axis)}"/>',
        f'    <limit lower="{num(lo)}" upper="{num(hi)}" effort="{num(effort)}" velocity="{num(velocity)}"/>',
        f'    <dynamics damping="{num(damping)}" friction="0"/>',
        "  </joint>"])


HEADER = """<?xml version="1.0"?>
<!--
  Leg rig: a single leg on a vertical rail (a hopping test rig). GENERATED by
  robots/leg_rig/make_leg_rig.py; do not edit: edit the script and run it again.
  Every number is chosen; robots/leg_rig/README.md gives the reasons.

  Root 'stand' (welded to the world: base: fixed); 'rail' a passive prismatic joint along
  z whose coordinate is the hip axis' height above the ground (m); 'hip' (rotary geared
  motor) and 'knee' (geared motor with a torsion spring) pitch about y; 'ankle' a passive
  pin. Hip negative swings the thigh forward, knee positive flexes it. All joints at 0:
  every link frame parallel to the world (x forward, y left, z up).
  Collision: the carriage (box), thigh and shank (cylinders), the foot's sole (box).
  Visuals: URDF boxes and cylinders, the same parts the masses and inertias come from.
-->
<robot name="leg_rig">
"""


def urdf_text():
    out = [HEADER.rstrip("\n")]
    out += [f'  <material name="{n}"><color rgba="{vec(c)}"/></material>' for n, c in MATERIALS]
    for name in LINKS:
        out.append(link_xml(name))
        for j in JOINTS:
            if j[2] == name:
                out.append(joint_xml(j))
    return "\n".join(out) + "\n</robot>\n"


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="\n") as f:
        f.write(text)
    os.replace(tmp, path)


# ----------------------------------------------------------------------------------
# Check (reads the file back; does not use the tables above except the expected names)
# ----------------------------------------------------------------------------------


def floats(s):
    return tuple(float(x) for x in s.split())


def check(path):
    root = ET.parse(path).getroot()
    ok = True

    def fail(msg):
        nonlocal ok
        ok = False
        print("FAIL: " + msg)

    links = {l.get("name"): l for l in root.findall("link")}
    joints = {j.get("name"): j for j in root.findall("joint")}
    if sorted(links) != sorted(LINKS):
        fail(f"links {sorted(links)}")
    if sorted(joints) != sorted(j[0] for j in JOINTS):
        fail(f"joints {sorted(joints)}")
    moving = 0.0
    for name, l in links.items():
        m = float(l.find("inertial/mass").get("value"))
        i = l.find("inertial/inertia")
        ixx, iyy, izz = (float(i.get(k)) for k in ("ixx", "iyy", "izz"))
        ixy, ixz, iyz = (float(i.get(k)) for k in ("ixy", "ixz", "iyz"))
        # Positive definite (leading minors) and the triangle inequality on the diagonal.
        d2 = ixx * iyy - ixy * ixy
        d3 = ixx * (iyy * izz - iyz * iyz) - ixy * (ixy * izz - iyz * ixz) + ixz * (ixy * iyz - iyy * ixz)
        if not (ixx > 0 and d2 > 0 and d3 > 0):
            fail(f"{name}: inertia not positive definite")
        if not (ixx + iyy > izz and iyy + izz > ixx and ixx + izz > iyy):
            fail(f"{name}: inertia violates the triangle inequality")
        com = floats(l.find("inertial/origin").get("xyz"))
        print(f"  {name:6s} {m:7.3f} kg  com ({com[0]:+.4f}, {com[1]:+.4f}, {com[2]:+.4f})  "
              f"I ({ixx:.5f}, {iyy:.5f}, {izz:.5f})")
        if name != "stand":
            moving += m
        cols = l.findall("collision")
        if (name == "stand") != (len(cols) == 0):
            fail(f"{name}: {len(cols)} collision shapes (the stand has none, every moving link one)")
    print(f"  moving mass {moving:.3f} kg (weight on the rail {moving * 9.81:.2f} N)")
    if not MOVING_MASS_RANGE_KG[0] <= moving <= MOVING_MASS_RANGE_KG[1]:
        fail(f"moving mass {moving} kg outside {MOVING_MASS_RANGE_KG}")
    # The crouch: foot under the hip, sole flat; its height below the hip.
    a = CROUCH_RAD
    knee_o = floats(joints["knee"].find("origin").get("xyz"))
    ankle_o = floats(joints["ankle"].find("origin").get("xyz"))
    sole = [c for c in links["foot"].findall("collision")][0]
    sz = floats(sole.find("geometry/box").get("size"))
    sole_z = floats(sole.find("origin").get("xyz"))[2] - sz[2] / 2
    thigh, shank = -knee_o[2], -ankle_o[2]
    x_foot = thigh * math.sin(a) - shank * math.sin(a)
    hip_height = thigh * math.cos(a) + shank * math.cos(a) - sole_z
    print(f"  crouch hip {-a}, knee {2 * a}, ankle {-a}: foot {x_foot:+.2e} m ahead of the hip, "
          f"hip axis {hip_height:.4f} m above the sole")
    if abs(x_foot) > 1e-12:
        fail("the crouch does not put the foot under the hip")
    lo, hi = floats(joints["rail"].find("limit").get("lower") + " " + joints["rail"].find("limit").get("upper"))
    if not lo < hip_height < hi:
        fail(f"the crouch's rail height {hip_height} is outside the rail's limits [{lo}, {hi}]")
    for name, want in (("hip", -a), ("knee", 2 * a), ("ankle", -a)):
        lim = joints[name].find("limit")
        if not float(lim.get("lower")) < want < float(lim.get("upper")):
            fail(f"{name}: the crouch's {want} outside its limits")
    print("check: " + ("ok" if ok else "FAILED"))
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="check the file on disk only")
    args = ap.parse_args()
    if not args.check:
        write_atomic(URDF_PATH, urdf_text())
        print(f"wrote {URDF_PATH}")
    return 0 if check(URDF_PATH) else 1


if __name__ == "__main__":
    sys.exit(main())
