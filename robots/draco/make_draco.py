#!/usr/bin/env python3
"""Generates DRACO's robot description: robots/draco/draco.urdf and robots/draco/meshes/*.obj.

    python3 robots/draco/make_draco.py           # write the URDF and meshes, then check them
    python3 robots/draco/make_draco.py --check   # only check the files on disk (exit 1 on failure)

Python 3 standard library only. The output is deterministic (same bytes on every run).

Sources (the project's DRACO facts sheet):
  * the paper: Ahn, Kim, Bang, Paine, Sentis, "Control of a High Performance Bipedal
    Robot using Viscoelastic Liquid Cooled Actuators": 1.30 m tall, 37 kg, 10 joints,
    ranges of motion 1.5 / 1.19 / 2.27 / 2.14 / 1.55 rad (hip rotation, abduction,
    flexion, knee, ankle);
  * the published 2019 robot description (left leg; right mirrors y): joint origins
    and axes, link masses, centres of mass and inertias, foot contact points, and the
    joint limits used on the real robot.
Where they disagree the paper wins (total mass, ranges of motion).

Conventions of THIS description (see README.md):
  * ankle zero = foot flat: the 2019 description rotated the ankle joint frame by
    -pi/2 about y (foot flat near q = pi/2); here the rotation is removed, so the foot
    frame is parallel to the shank frame at q = 0 and the ankle limits are shifted by
    -pi/2;
  * every joint at 0 = standing straight, feet flat; all link frames are parallel to
    the torso frame in that pose (x forward, y left, z up);
  * the mass missing from the 2019 description (37 - 36.21 kg) is in the torso.
The visual meshes are procedural (rounded boxes and lathed solids), closed, outward
facing, with vertex normals; their shapes follow the paper's description of where
the actuators sit (hip rotation near the pelvis, abduction on the outer hip, hip
flexion on the upper thigh, knee on the lower thigh, ankle on the calf).
"""

import argparse
import math
import os
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
URDF_PATH = os.path.join(HERE, "draco.urdf")
MESH_DIR = os.path.join(HERE, "meshes")
PACKAGE = "package://draco/"

# ----------------------------------------------------------------------------------
# Facts (SI units). Left leg; the right leg mirrors y.
# ----------------------------------------------------------------------------------
PAPER_HEIGHT_M = 1.30
PAPER_MASS_KG = 37.0
# Paper, Fig. 2 caption: ranges of motion (upper - lower), rad.
PAPER_ROM = {"hip_yaw": 1.5, "hip_roll": 1.19, "hip_pitch": 2.27, "knee": 2.14, "ankle": 1.55}

# Joint origins in the parent link frame (2019 description); no rotations here (the
# ankle's -pi/2 is removed, see the docstring).
HIP_YAW_XYZ = (-0.0222, 0.087, 0.0)    # torso -> hip_yaw_link, axis z
HIP_ROLL_XYZ = (0.0, 0.07, -0.02)      # hip_yaw_link -> hip_roll_link, axis x
HIP_PITCH_XYZ = (0.0, 0.010, -0.065)   # hip_roll_link -> thigh, axis y
KNEE_XYZ = (0.0, -0.0168, -0.48)       # thigh -> shank, axis y
ANKLE_XYZ = (0.0011, 0.0168, -0.48)    # shank -> foot, axis y
ANKLE_SHIFT_RAD = math.pi / 2          # description's ankle angle - this project's

# Masses (kg) and centres of mass (link frame, m) of the 2019 description.
M_TORSO_2019 = 9.67
M_HIP_YAW, M_HIP_ROLL, M_THIGH, M_SHANK, M_FOOT = 2.962, 0.408, 6.0, 3.5, 0.4
COM_TORSO = (-0.0134, 0.0008, 0.108)
COM_HIP_YAW = (0.0, 0.07, 0.05)
COM_HIP_ROLL = (0.0, 0.022, -0.02)
COM_THIGH = (0.0009, 0.0066, -0.24)
COM_SHANK = (0.0161, 0.0167, -0.275)
COM_FOOT = (0.0108, 0.0, -0.0443)
# Inertias about the CoM, (ixx, ixy, ixz, iyy, iyz, izz), kg m^2.
I_TORSO_2019 = (0.0585, 0.0, -0.0061, 0.0652, 0.0, 0.0178)
I_THIGH = (0.0555, 0.0, 0.0, 0.0595, 0.0, 0.0059)
# The 2019 shank (0.0224, 0.0240, 0.0016) sits exactly on the triangle inequality
# (Ixx + Izz = Iyy: a body with no extent in y). Its second moments int x^2 dm =
# 0.0016 and int z^2 dm = 0.0224 are kept and int y^2 dm is raised from 0 to 0.0002
# kg m^2 (7.6 mm radius of gyration across the leg): Ixx 0.0226, Izz 0.0018.
I_SHANK = (0.0226, 0.0, 0.0, 0.0240, 0.0, 0.0018)

# The 2019 description gives "small" inertias for these; here: uniform boxes of the
# link's mass and of the size of its main parts (m).
BOX_HIP_YAW = (0.08, 0.12, 0.14)    # yaw bearing, lateral arm, abduction actuator
BOX_HIP_ROLL = (0.06, 0.05, 0.09)   # roll hub and hip-pitch fork
BOX_FOOT = (0.154, 0.035, 0.05)     # sole bar and ankle upright

# Foot contact points (foot frame; the 2019 values, unchanged by removing the -pi/2:
# at q_2019 = pi/2 the 2019 foot frame equals this one), sphere radius.
CONTACT_X = {"toe": 0.08, "heel": -0.05}
CONTACT_Y = {"left": 0.005, "right": -0.005}
CONTACT_Z = -0.044
CONTACT_RADIUS = 0.03

# Joint limits of the real robot (2019; left leg; the ankle in the 2019 convention).
REAL_LIMITS_2019 = {"hip_yaw": (-0.746, 0.746), "hip_roll": (-0.277, 0.901), "hip_pitch": (-1.263, 1.001),
                    "knee": (0.0, 2.0), "ankle": (0.733, 2.269)}


def paper_limits(kind):
    """This project's limits: the real robot's, shifted to this project's ankle zero and
    widened symmetrically to exactly the paper's range of motion (to 1 mrad); the knee
    keeps 0 (straight) as its lower limit. Right leg: see MIRRORED_JOINTS."""
    lo, hi = REAL_LIMITS_2019[kind]
    if kind == "ankle":
        lo, hi = lo - ANKLE_SHIFT_RAD, hi - ANKLE_SHIFT_RAD
    rom = PAPER_ROM[kind]
    lo = 0.0 if kind == "knee" else round((lo + hi) / 2 - rom / 2, 3)
    return lo, round(lo + rom, 9)


# hip yaw [-0.75, 0.75], roll [-0.283, 0.907], pitch [-1.266, 1.004], knee [0, 2.14],
# ankle [-0.845, 0.705] (the real robot's [0.733, 2.269] - pi/2 = [-0.838, 0.698], widened)
LIMITS_LEFT = {kind: paper_limits(kind) for kind in PAPER_ROM}
MIRRORED_JOINTS = ("hip_yaw", "hip_roll")   # axis z and x: the mirror negates the angle
EFFORT_NM = {"hip_yaw": 150.0, "hip_roll": 200.0, "hip_pitch": 200.0, "knee": 200.0, "ankle": 20.0}
VELOCITY_RADS = {"hip_yaw": 12.0, "hip_roll": 12.0, "hip_pitch": 20.0, "knee": 20.0, "ankle": 25.0}

# Visual sizing. The sole visual ends 0.5 mm above the contact spheres' bottoms, so the
# spheres are the lowest points; the torso's top is placed so that the visual extent
# of the default pose is the paper's 1.30 m.
SOLE_BOTTOM_Z = CONTACT_Z - CONTACT_RADIUS + 0.0005       # foot frame: -0.0735
ANKLE_Z_WORLD = HIP_ROLL_XYZ[2] + HIP_PITCH_XYZ[2] + KNEE_XYZ[2] + ANKLE_XYZ[2]  # -1.045
TORSO_TOP_Z = round(PAPER_HEIGHT_M + ANKLE_Z_WORLD + SOLE_BOTTOM_Z, 6)           # 0.1815

MATERIALS = [  # name, rgba
    ("structure", (0.22, 0.23, 0.25, 1.0)),    # anodised aluminium frame, dark grey
    ("actuator", (0.10, 0.30, 0.68, 1.0)),     # VLCA bodies, blue
    ("jacket", (0.95, 0.47, 0.10, 1.0)),       # liquid-cooling motor jackets, orange
    ("steel", (0.74, 0.75, 0.77, 1.0)),        # ball-screw rods, axles
    ("cooling", (0.58, 0.64, 0.70, 1.0)),      # radiator, pump, reservoir
    ("electronics", (0.07, 0.07, 0.08, 1.0)),  # boards, IMU
    ("rubber", (0.04, 0.04, 0.04, 1.0)),       # sole pads
]

# ----------------------------------------------------------------------------------
# Small vector and matrix helpers (tuples; matrices are tuples of rows).
# ----------------------------------------------------------------------------------


def vadd(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def vsub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def vmul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    n = norm(a)
    return (a[0] / n, a[1] / n, a[2] / n)


def mat_vec(m, v):
    return tuple(m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] for i in range(3))


def mat_mul(a, b):
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))


IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def rpy_matrix(rpy):
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = ((1, 0, 0), (0, cr, -sr), (0, sr, cr))
    ry = ((cp, 0, sp), (0, 1, 0), (-sp, 0, cp))
    rz = ((cy, -sy, 0), (sy, cy, 0), (0, 0, 1))
    return mat_mul(rz, mat_mul(ry, rx))


def frame_along(d):
    """Rotation whose third column is unit(d); the first column is as close to x as possible."""
    d = unit(d)
    helper = (1.0, 0.0, 0.0) if abs(d[0]) < 0.9 else (0.0, 1.0, 0.0)
    e1 = unit(vsub(helper, vmul(d, dot(helper, d))))
    e2 = cross(d, e1)
    return tuple((e1[i], e2[i], d[i]) for i in range(3))


# ----------------------------------------------------------------------------------
# Triangle meshes
# ----------------------------------------------------------------------------------


class Mesh:
    """Indexed triangles; each corner has a position index and a normal index.

    Positions are shared within a part (so each part is a closed, consistently wound
    surface); parts appended with `add` keep their own positions.
    """

    def __init__(self):
        self.positions = []
        self.normals = []
        self.triangles = []   # ((p0, n0), (p1, n1), (p2, n2)), counter-clockwise seen from outside

    def add(self, other):
        po, no = len(self.positions), len(self.normals)
        self.positions.extend(other.positions)
        self.normals.extend(other.normals)
        for tri in other.triangles:
            self.triangles.append(tuple((p + po, n + no) for p, n in tri))
        return self

    def transformed(self, rot, trans):
        out = Mesh()
        out.positions = [vadd(mat_vec(rot, p), trans) for p in self.positions]
        out.normals = [unit(mat_vec(rot, n)) for n in self.normals]
        out.triangles = list(self.triangles)
        return out

    def mirrored_y(self):
        out = Mesh()
        out.positions = [(p[0], -p[1], p[2]) for p in self.positions]
        out.normals = [(n[0], -n[1], n[2]) for n in self.normals]
        out.triangles = [(t[0], t[2], t[1]) for t in self.triangles]   # a mirror flips the winding
        return out


class _Builder:
    """Collects positions with welding (by exact local coordinates) and normals."""

    def __init__(self):
        self.mesh = Mesh()
        self._pidx = {}
        self._nidx = {}

    def pos(self, p):
        key = (round(p[0], 10), round(p[1], 10), round(p[2], 10))
        i = self._pidx.get(key)
        if i is None:
            i = len(self.mesh.positions)
            self._pidx[key] = i
            self.mesh.positions.append(p)
        return i

    def nrm(self, n):
        n = unit(n)
        key = (round(n[0], 10), round(n[1], 10), round(n[2], 10))
        i = self._nidx.get(key)
        if i is None:
            i = len(self.mesh.normals)
            self._nidx[key] = i
            self.mesh.normals.append(n)
        return i

    def tri(self, a, b, c):
        if a[0] == b[0] or b[0] == c[0] or a[0] == c[0]:
            return  # degenerate (a pole of a lathe)
        self.mesh.triangles.append((a, b, c))


def rounded_box(half, radius, steps=2):
    """Box of half extents `half` centred at the origin, edges and corners rounded with
    `radius`; `steps` samples per 45 degrees of each rounded edge. Smooth normals."""
    r = radius
    inner = [h - r for h in half]
    assert all(i >= 0 for i in inner), (half, radius)

    def samples(axis):
        s = [inner[axis] + r * math.tan(math.radians(45.0 * k / steps)) for k in range(1, steps + 1)]
        vals = [-v for v in reversed(s)] + ([-inner[axis], inner[axis]] if inner[axis] > 0 else [0.0]) + s
        return vals

    b = _Builder()
    for axis in range(3):
        for sign in (1.0, -1.0):
            ua, va = ((axis + 1) % 3, (axis + 2) % 3) if sign > 0 else ((axis + 2) % 3, (axis + 1) % 3)
            us, vs = samples(ua), samples(va)
            grid = []
            for u in us:
                row = []
                for v in vs:
                    p = [0.0, 0.0, 0.0]
                    p[axis] = sign * half[axis]
                    p[ua], p[va] = u, v
                    c = [max(-inner[k], min(inner[k], p[k])) for k in range(3)]
                    off = unit((p[0] - c[0], p[1] - c[1], p[2] - c[2]))
                    q = (c[0] + r * off[0], c[1] + r * off[1], c[2] + r * off[2])
                    row.append((b.pos(q), b.nrm(off)))
                grid.append(row)
            for i in range(len(us) - 1):
                for j in range(len(vs) - 1):
                    p00, p10, p11, p01 = grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]
                    b.tri(p00, p10, p11)
                    b.tri(p00, p11, p01)
    return b.mesh


def lathe(profile, segments=20):
    """Solid of revolution about z. `profile`: (r, z) points from the bottom pole (r = 0)
    to the top pole (r = 0), outline counter-clockwise in the (r, z) half plane.
    Normals are smooth around z and per profile segment along it (sharp profile corners)."""
    assert profile[0][0] == 0 and profile[-1][0] == 0
    b = _Builder()
    angles = [2 * math.pi * k / segments for k in range(segments)]
    rings = [[b.pos((r * math.cos(a), r * math.sin(a), z)) for a in angles] for (r, z) in profile]
    for i, ((r0, z0), (r1, z1)) in enumerate(zip(profile, profile[1:])):
        n_r, n_z = unit((z1 - z0, 0.0, -(r1 - r0)))[0::2]   # outward normal in the (r, z) plane
        ns = [b.nrm((n_r * math.cos(a), n_r * math.sin(a), n_z)) for a in angles]
        for k in range(segments):
            k1 = (k + 1) % segments
            a0, b0 = (rings[i][k], ns[k]), (rings[i][k1], ns[k1])
            a1, b1 = (rings[i + 1][k], ns[k]), (rings[i + 1][k1], ns[k1])
            b.tri(a0, b0, b1)
            b.tri(a0, b1, a1)
    return b.mesh


def cylinder_profile(radius, length, bevel=0.0):
    """Profile of a closed cylinder from z = 0 to z = length, edges bevelled."""
    if bevel <= 0:
        return [(0.0, 0.0), (radius, 0.0), (radius, length), (0.0, length)]
    return [(0.0, 0.0), (radius - bevel, 0.0), (radius, bevel), (radius, length - bevel),
            (radius - bevel, length), (0.0, length)]


def place_along(mesh, p0, p1):
    """Puts a mesh built along +z (from z = 0) on the segment p0 -> p1."""
    return mesh.transformed(frame_along(vsub(p1, p0)), p0)


def auto_segments(radius):
    """Segments around a circle: chords of about 1 cm, between 8 and 24, even."""
    n = int(math.ceil(2 * math.pi * radius / 0.01))
    return max(8, min(24, n + (n % 2)))


def cylinder_between(p0, p1, radius, bevel=0.0, segments=None):
    if segments is None:
        segments = auto_segments(radius)
    if radius < 0.015:
        bevel = 0.0   # invisible at this size
    return place_along(lathe(cylinder_profile(radius, norm(vsub(p1, p0)), bevel), segments), p0, p1)


def cylinder_y(center, radius, half_width, bevel=0.0, segments=None):
    return cylinder_between((center[0], center[1] - half_width, center[2]),
                            (center[0], center[1] + half_width, center[2]), radius, bevel, segments)


def cylinder_x(center, radius, half_width, bevel=0.0, segments=None):
    return cylinder_between((center[0] - half_width, center[1], center[2]),
                            (center[0] + half_width, center[1], center[2]), radius, bevel, segments)


def flat_box(half):
    """Plain box (8 positions, flat normals) centred at the origin."""
    b = _Builder()
    for axis in range(3):
        for sign in (1.0, -1.0):
            ua, va = ((axis + 1) % 3, (axis + 2) % 3) if sign > 0 else ((axis + 2) % 3, (axis + 1) % 3)
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            ni = b.nrm(tuple(n))
            corners = []
            for u, v in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[ua], p[va] = sign * half[axis], u * half[ua], v * half[va]
                corners.append((b.pos(tuple(p)), ni))
            b.tri(corners[0], corners[1], corners[2])
            b.tri(corners[0], corners[2], corners[3])
    return b.mesh


# Edges rounded with a radius at most this are drawn sharp (under a pixel in renders
# of the whole robot; keeps the meshes small).
SHARP_RADIUS = 0.004


def box(center, half, radius, steps=1):
    m = flat_box(half) if radius <= SHARP_RADIUS else rounded_box(half, radius, steps)
    return m.transformed(IDENTITY, center)


def beam_between(p0, p1, half_xy, radius, steps=1):
    """Rounded bar from p0 to p1 (its ends at p0 and p1), cross-section half extents half_xy."""
    length = norm(vsub(p1, p0))
    m = rounded_box((half_xy[0], half_xy[1], length / 2), radius, steps)
    return m.transformed(frame_along(vsub(p1, p0)), vmul(vadd(p0, p1), 0.5))


def actuator_body(p_motor_end, p_nose_end, motor_radius, motor_length, tube_radius, segments=None):
    """A VLCA housing along p_motor_end -> p_nose_end: motor section (cooling-jacket
    seat), ball-screw tube, nose with the rod seal. The rod itself is a URDF cylinder."""
    L = norm(vsub(p_nose_end, p_motor_end))
    rm, rt, b = motor_radius, tube_radius, 0.002
    prof = [(0.0, 0.0), (rm - 2 * b, 0.0), (rm, 2 * b), (rm, motor_length - b), (rt + b, motor_length),
            (rt, motor_length + b), (rt, L - 0.012), (rt * 0.6, L - 0.004), (rt * 0.45, L), (0.0, L)]
    return place_along(lathe(prof, segments or auto_segments(motor_radius)), p_motor_end, p_nose_end)


def jacket_ring(p_motor_end, p_nose_end, start, length, radius, segments=None):
    """Cooling jacket around a motor: a short bevelled cylinder on the actuator axis."""
    d = unit(vsub(p_nose_end, p_motor_end))
    a = vadd(p_motor_end, vmul(d, start))
    return cylinder_between(a, vadd(a, vmul(d, length)), radius, 0.0015, segments)


def merge(*meshes):
    out = Mesh()
    for m in meshes:
        out.add(m)
    return out


# ----------------------------------------------------------------------------------
# Link geometry (left side; the right side is the mirror image in y).
# Returns {mesh name (without side prefix): (material, Mesh)} and a list of primitive
# visuals (name, material, xyz, rpy, ("cylinder", r, L) | ("box", (sx, sy, sz))).
# ----------------------------------------------------------------------------------
HALF_PI = math.pi / 2
ALONG_Y = (HALF_PI, 0.0, 0.0)   # URDF cylinders are along z; this turns them onto y
ALONG_X = (0.0, HALF_PI, 0.0)
ALONG_Z = (0.0, 0.0, 0.0)

# Actuator pivots (link frames, default pose). A linear actuator acts between a pivot
# on one link and a lever pivot on the next; the rod ends are at the lever pivots.
ROLL_ACT_TOP = (0.0, 0.12, 0.145)        # hip_yaw_link: abduction actuator, motor end
ROLL_ACT_ROD = (0.0, 0.12, -0.02)        # = hip_roll_link lever pivot (0, 0.05, 0)
PITCH_ACT_BOTTOM = (0.05, 0.0, -0.275)   # thigh: hip flexion actuator, motor end
PITCH_ACT_ROD = (0.05, 0.0, 0.025)       # = hip_roll_link lever pivot (0.05, 0.01, -0.04)
KNEE_ACT_TOP = (-0.052, KNEE_XYZ[1], -0.185)   # thigh: knee actuator, motor end
KNEE_ACT_ROD = (-0.052, KNEE_XYZ[1], KNEE_XYZ[2])  # = shank lever pivot (-0.052, 0, 0)
ANKLE_LEVER = 0.0665                               # foot heel lever (m)
ANKLE_ACT_TOP = (ANKLE_XYZ[0] - ANKLE_LEVER, ANKLE_XYZ[1], ANKLE_XYZ[2] + 0.30)  # shank (calf), motor end
ANKLE_ACT_ROD = (ANKLE_XYZ[0] - ANKLE_LEVER, ANKLE_XYZ[1], ANKLE_XYZ[2])  # = foot heel lever pivot
# Sizes match the linkages of actuators.yaml roughly (pivot distance a ~ 0.28 / 0.30 / 0.30 m,
# lever b ~ 0.055 / 0.052 / 0.0665 m for hip flexion / knee / ankle); the lever angles are
# drawn square to the actuator at q = 0 (the visuals do not move with the linkage).


def rod_cylinder(name, p_from, p_to, radius):
    """A URDF cylinder visual for an actuator rod (nearly vertical: axis along z)."""
    c = vmul(vadd(p_from, p_to), 0.5)
    d = vsub(p_to, p_from)
    assert abs(d[1]) < 1e-12 and abs(d[2]) > 0.99 * norm(d)
    # Tilt (the ankle rod leans by 1.1 mm over 0.41 m): express it with a pitch angle.
    pitch = math.atan2(d[0], d[2]) if d[2] > 0 else math.atan2(-d[0], -d[2])
    return (name, "steel", c, (0.0, pitch, 0.0), ("cylinder", radius, norm(d)))


def torso_geometry():
    top = TORSO_TOP_Z
    body_bottom = 0.05
    yaw_x = HIP_YAW_XYZ[0]
    structure = merge(
        # electronics body (pelvis): rounded box from the pelvis plate to the top
        box((-0.02, 0.0, (body_bottom + top) / 2), (0.09, 0.10, (top - body_bottom) / 2), 0.02, steps=2),
        # pelvis plate carrying the hip yaw bearings
        box((yaw_x, 0.0, 0.042), (0.065, 0.15, 0.012), 0.006),
        # side rails along the body (lifting points)
        box((-0.02, 0.1035, 0.135), (0.07, 0.006, 0.01), 0.004),
        box((-0.02, -0.1035, 0.135), (0.07, 0.006, 0.01), 0.004),
    )
    for s in (1, -1):
        # stationary ring of the hip yaw bearing, under the plate
        structure.add(cylinder_between((yaw_x, s * HIP_YAW_XYZ[1], 0.015), (yaw_x, s * HIP_YAW_XYZ[1], 0.031),
                                       0.045, 0.003, 24))
        # clevis blocks of the hip-rotation actuators on the plate
        structure.add(box((-0.095, s * 0.125, 0.071), (0.012, 0.016, 0.017), 0.004))
        structure.add(box((0.052, s * 0.125, 0.068), (0.01, 0.012, 0.014), 0.004))
    actuators, jackets = Mesh(), Mesh()
    for s in (1, -1):
        # hip-rotation actuators: horizontal, on the pelvis plate, outboard of the body
        a, b = (-0.09, s * 0.125, 0.077), (0.05, s * 0.125, 0.077)
        actuators.add(actuator_body(a, b, 0.021, 0.05, 0.016))
        jackets.add(jacket_ring(a, b, 0.008, 0.036, 0.0225))
    cooling = Mesh()
    # radiator on the back: fins between two manifolds
    for i in range(7):
        z = 0.078 + 0.0135 * i
        cooling.add(box((-0.117, 0.0, z), (0.009, 0.075, 0.002), 0.0015))
    for z in (0.066, 0.166):
        cooling.add(box((-0.116, 0.0, z), (0.01, 0.082, 0.006), 0.004))
    # pump and reservoir below the radiator
    cooling.add(cylinder_y((-0.122, 0.0, 0.038), 0.017, 0.075, 0.003))
    cooling.add(cylinder_between((-0.122, 0.045, 0.05), (-0.122, 0.045, 0.07), 0.006, 0.0))
    cooling.add(cylinder_between((-0.122, -0.045, 0.05), (-0.122, -0.045, 0.07), 0.006, 0.0))
    electronics = Mesh()
    # embedded controller boards behind the front cover
    for i in range(3):
        electronics.add(box((0.077, 0.0, 0.072 + 0.031 * i), (0.008, 0.085, 0.012), 0.003))
    for y in (-0.06, -0.03, 0.0, 0.03, 0.06):
        electronics.add(box((0.087, y, 0.072), (0.004, 0.008, 0.005), 0.0015))
    meshes = {
        "torso": ("structure", structure),
        "torso_actuators": ("actuator", actuators),
        "torso_jackets": ("jacket", jackets),
        "torso_cooling": ("cooling", cooling),
        "torso_electronics": ("electronics", electronics),
    }
    prims = [("imu", "electronics", (0.094, 0.0, 0.165), (0.0, 0.0, 0.0), ("box", (0.016, 0.04, 0.022)))]
    return meshes, prims


def hip_yaw_geometry():
    ry, rz = HIP_ROLL_XYZ[1], HIP_ROLL_XYZ[2]
    structure = merge(
        # rotating flange of the yaw bearing and its hub
        cylinder_between((0, 0, 0.0), (0, 0, 0.015), 0.045, 0.002),
        cylinder_between((0, 0, -0.014), (0, 0, 0.0), 0.03, 0.002),
        # lateral arm out to the abduction bearings
        box((0.0, 0.05, -0.003), (0.035, 0.06, 0.009), 0.004),
        # abduction (roll) bearing bosses, axis x
        cylinder_x((0.04, ry, rz), 0.026, 0.008, 0.002),
        cylinder_x((-0.04, ry, rz), 0.026, 0.008, 0.002),
        # upright carrying the abduction actuator's trunnion, and the trunnion pin
        box((-0.032, 0.12, 0.06), (0.007, 0.022, 0.07), 0.003),
        cylinder_x((-0.024, 0.12, 0.118), 0.007, 0.009, 0.001),
    )
    actuator = actuator_body(ROLL_ACT_TOP, (0.0, 0.12, 0.022), 0.022, 0.055, 0.016)
    jacket = jacket_ring(ROLL_ACT_TOP, (0.0, 0.12, 0.022), 0.008, 0.04, 0.0235)
    meshes = {"hip_yaw_link": ("structure", structure), "hip_yaw_actuator": ("actuator", actuator),
              "hip_yaw_jacket": ("jacket", jacket)}
    prims = [rod_cylinder("abduction_rod", ROLL_ACT_ROD, (0.0, 0.12, 0.024), 0.006)]
    return meshes, prims


def hip_roll_geometry():
    py, pz = HIP_PITCH_XYZ[1], HIP_PITCH_XYZ[2]
    structure = merge(
        # roll hub between the yaw link's bosses
        cylinder_x((0, 0, 0), 0.024, 0.031, 0.002),
        # lever of the abduction actuator and its rod eye
        box((0.0, 0.03, 0.0), (0.01, 0.026, 0.01), 0.003),
        cylinder_x((0.0, 0.05, 0.0), 0.011, 0.012, 0.0015),
        # bridge and cheeks of the hip-flexion fork
        box((0.0, py, -0.012), (0.028, 0.046, 0.011), 0.004),
        box((0.0, py + 0.038, -0.045), (0.024, 0.006, 0.035), 0.003),
        box((0.0, py - 0.038, -0.045), (0.024, 0.006, 0.035), 0.003),
        cylinder_y((0.0, py + 0.038, pz), 0.032, 0.008, 0.002),
        cylinder_y((0.0, py - 0.038, pz), 0.032, 0.008, 0.002),
        # lever of the hip-flexion actuator and its rod eye
        box((0.04, py, -0.027), (0.018, 0.01, 0.014), 0.003),
        cylinder_y((0.05, py, -0.04), 0.011, 0.014, 0.0015),
    )
    prims = [("roll_axle", "steel", (0.0, 0.0, 0.0), ALONG_X, ("cylinder", 0.01, 0.104))]
    return {"hip_roll_link": ("structure", structure)}, prims


def thigh_geometry():
    ky, kz = KNEE_XYZ[1], KNEE_XYZ[2]
    structure = merge(
        # hip-flexion hub (between the hip roll link's fork)
        cylinder_y((0, 0, 0), 0.03, 0.028, 0.003),
        # structural beam hip -> knee
        beam_between((0.0, 0.0, -0.02), (0.0, ky, kz + 0.035), (0.024, 0.02), 0.008),
        # knee fork: bridge, cheeks, bearing bosses
        box((0.0, ky, kz + 0.035), (0.024, 0.04, 0.012), 0.004),
        box((0.0, ky + 0.034, kz + 0.01), (0.022, 0.006, 0.028), 0.003),
        box((0.0, ky - 0.034, kz + 0.01), (0.022, 0.006, 0.028), 0.003),
        cylinder_y((0.0, ky + 0.034, kz), 0.03, 0.007, 0.002),
        cylinder_y((0.0, ky - 0.034, kz), 0.03, 0.007, 0.002),
        # trunnion lugs of the hip-flexion (front) and knee (back) actuators
        box((0.034, 0.0, -0.27), (0.014, 0.026, 0.013), 0.003),
        box((-0.035, ky * 0.45, -0.195), (0.015, 0.026, 0.013), 0.003),
    )
    pitch_nose = (0.05, 0.0, -0.085)
    knee_nose = (-0.052, ky, -0.37)
    actuators = merge(
        actuator_body(PITCH_ACT_BOTTOM, pitch_nose, 0.026, 0.07, 0.02),
        actuator_body(KNEE_ACT_TOP, knee_nose, 0.026, 0.065, 0.02),
    )
    jackets = merge(
        jacket_ring(PITCH_ACT_BOTTOM, pitch_nose, 0.01, 0.05, 0.0275),
        jacket_ring(KNEE_ACT_TOP, knee_nose, 0.01, 0.045, 0.0275),
    )
    meshes = {"thigh": ("structure", structure), "thigh_actuators": ("actuator", actuators),
              "thigh_jackets": ("jacket", jackets)}
    prims = [
        ("hip_pitch_axle", "steel", (0.0, 0.0, 0.0), ALONG_Y, ("cylinder", 0.012, 0.1)),
        rod_cylinder("hip_pitch_rod", (0.05, 0.0, -0.089), PITCH_ACT_ROD, 0.008),
        rod_cylinder("knee_rod", KNEE_ACT_ROD, (-0.052, ky, -0.366), 0.008),
    ]
    return meshes, prims


def shank_geometry():
    ax, ay, az = ANKLE_XYZ
    structure = merge(
        # knee hub between the thigh's fork
        cylinder_y((0, 0, 0), 0.026, 0.026, 0.002),
        # knee lever (behind the axis) and its rod eye
        box((-0.033, 0.0, 0.0), (0.027, 0.012, 0.011), 0.003),
        cylinder_y((-0.052, 0.0, 0.0), 0.011, 0.016, 0.0015),
        # structural beam knee -> ankle
        beam_between((0.012, 0.0, -0.02), (0.004, ay, az + 0.035), (0.021, 0.017), 0.007),
        # ankle fork: bridge, cheeks, bearing bosses
        box((ax, ay, az + 0.035), (0.022, 0.034, 0.01), 0.004),
        box((ax, ay + 0.028, az + 0.01), (0.018, 0.005, 0.024), 0.003),
        box((ax, ay - 0.028, az + 0.01), (0.018, 0.005, 0.024), 0.003),
        cylinder_y((ax, ay + 0.028, az), 0.024, 0.006, 0.0015),
        cylinder_y((ax, ay - 0.028, az), 0.024, 0.006, 0.0015),
        # trunnion lug of the ankle actuator (calf)
        box((-0.036, 0.011, ANKLE_ACT_TOP[2] - 0.01), (0.03, 0.016, 0.011), 0.003),
    )
    nose = (ANKLE_ACT_ROD[0], ay, az + 0.105)
    actuator = actuator_body(ANKLE_ACT_TOP, nose, 0.02, 0.06, 0.014)
    jacket = jacket_ring(ANKLE_ACT_TOP, nose, 0.008, 0.044, 0.0215)
    meshes = {"shank": ("structure", structure), "shank_actuator": ("actuator", actuator),
              "shank_jacket": ("jacket", jacket)}
    prims = [
        ("knee_axle", "steel", (0.0, 0.0, 0.0), ALONG_Y, ("cylinder", 0.011, 0.092)),
        rod_cylinder("ankle_rod", ANKLE_ACT_ROD, vadd(nose, (0.0, 0.0, 0.004)), 0.005),
    ]
    return meshes, prims


def foot_geometry():
    sole_top, sole_bottom = -0.044, -0.063
    structure = merge(
        # ankle hub between the shank's fork
        cylinder_y((0, 0, 0), 0.02, 0.021, 0.0015),
        # heel lever of the ankle actuator and its rod eye
        box((-0.036, 0.0, 0.0), (0.031, 0.008, 0.009), 0.003),
        cylinder_y((-ANKLE_LEVER, 0.0, 0.0), 0.009, 0.011, 0.0015),
        # upright from the ankle to the sole
        box((0.006, 0.0, -0.028), (0.018, 0.012, 0.022), 0.004),
        # line foot: narrow sole bar, 15.4 cm overall, contact pads 13 cm apart
        box((0.015, 0.0, (sole_top + sole_bottom) / 2), (0.077, 0.0175, (sole_top - sole_bottom) / 2), 0.007,
            steps=2),
    )
    pad_h = (sole_bottom + 0.0005 - SOLE_BOTTOM_Z) / 2     # pads overlap the bar by 0.5 mm
    sole = Mesh()
    for x in (CONTACT_X["toe"], CONTACT_X["heel"]):
        sole.add(box((x, 0.0, SOLE_BOTTOM_Z + pad_h), (0.011, 0.0165, pad_h), 0.0045))
    prims = [("ankle_axle", "steel", (0.0, 0.0, 0.0), ALONG_Y, ("cylinder", 0.009, 0.076))]
    return {"foot": ("structure", structure), "foot_sole": ("rubber", sole)}, prims


# ----------------------------------------------------------------------------------
# Robot assembly
# ----------------------------------------------------------------------------------


def box_inertia(m, dims):
    x, y, z = dims
    return (m / 12 * (y * y + z * z), 0.0, 0.0, m / 12 * (x * x + z * z), 0.0, m / 12 * (x * x + y * y))


def mirror_inertia(i):
    ixx, ixy, ixz, iyy, iyz, izz = i
    return (ixx, -ixy, ixz, iyy, -iyz, izz)


def mirror_xyz(p):
    return (p[0], -p[1], p[2])


def mirror_rpy(rpy):
    return (-rpy[0], rpy[1], -rpy[2])


def leg_masses():
    return M_HIP_YAW + M_HIP_ROLL + M_THIGH + M_SHANK + M_FOOT


TORSO_MASS = round(PAPER_MASS_KG - 2 * leg_masses(), 9)                  # 10.46
TORSO_SCALE = TORSO_MASS / M_TORSO_2019
I_TORSO = tuple(v * TORSO_SCALE for v in I_TORSO_2019)


def build_robot():
    """Links (with meshes and primitives) and joints, left then right leg."""
    links, joints, meshes = [], [], {}

    def add_link(name, mass, com, inertia, geo, comment=""):
        mesh_dict, prims = geo
        visuals = []
        for mname, (material, mesh) in mesh_dict.items():
            meshes[mname] = mesh
            visuals.append({"name": mname, "material": material, "xyz": (0, 0, 0), "rpy": (0, 0, 0),
                            "geometry": ("mesh", mname)})
        for (pname, material, xyz, rpy, g) in prims:
            visuals.append({"name": pname, "material": material, "xyz": xyz, "rpy": rpy, "geometry": g})
        links.append({"name": name, "mass": mass, "com": com, "inertia": inertia, "visuals": visuals,
                      "collisions": [], "comment": comment})
        return links[-1]

    add_link("torso", TORSO_MASS, COM_TORSO, I_TORSO, torso_geometry(),
             "Root link (floating base in simulation). 9.67 kg in the 2019 description; the paper's 37 kg "
             "total puts %.2f kg more here (wiring, cooling liquid, boards), spread like the rest of the "
             "torso: same CoM, inertia scaled by %.2f / 9.67." % (TORSO_MASS - M_TORSO_2019, TORSO_MASS))

    leg_geo = [("hip_yaw_link", M_HIP_YAW, COM_HIP_YAW, box_inertia(M_HIP_YAW, BOX_HIP_YAW), hip_yaw_geometry()),
               ("hip_roll_link", M_HIP_ROLL, COM_HIP_ROLL, box_inertia(M_HIP_ROLL, BOX_HIP_ROLL),
                hip_roll_geometry()),
               ("thigh", M_THIGH, COM_THIGH, I_THIGH, thigh_geometry()),
               ("shank", M_SHANK, COM_SHANK, I_SHANK, shank_geometry()),
               ("foot", M_FOOT, COM_FOOT, box_inertia(M_FOOT, BOX_FOOT), foot_geometry())]
    joint_defs = [("hip_yaw", "torso", "hip_yaw_link", HIP_YAW_XYZ, (0, 0, 1)),
                  ("hip_roll", "hip_yaw_link", "hip_roll_link", HIP_ROLL_XYZ, (1, 0, 0)),
                  ("hip_pitch", "hip_roll_link", "thigh", HIP_PITCH_XYZ, (0, 1, 0)),
                  ("knee", "thigh", "shank", KNEE_XYZ, (0, 1, 0)),
                  ("ankle", "shank", "foot", ANKLE_XYZ, (0, 1, 0))]
    box_note = {"hip_yaw_link": BOX_HIP_YAW, "hip_roll_link": BOX_HIP_ROLL, "foot": BOX_FOOT}

    for side in ("l", "r"):
        mir = side == "r"
        for (lname, mass, com, inertia, (mesh_dict, prims)) in leg_geo:
            md = {}
            for mname, (material, mesh) in mesh_dict.items():
                md["%s_%s" % (side, mname)] = (material, mesh.mirrored_y() if mir else mesh)
            pr = []
            for (pname, material, xyz, rpy, g) in prims:
                pr.append(("%s_%s" % (side, pname), material, mirror_xyz(xyz) if mir else xyz,
                           mirror_rpy(rpy) if mir else rpy, g))
            comment = ""
            if lname in box_note:
                comment = ("Inertia: uniform box %g x %g x %g m of the link's mass (the 2019 description "
                           "only gives small values)." % box_note[lname])
            if lname == "shank":
                comment = ("Inertia: 2019 values with int y^2 dm raised from 0 to 0.0002 kg m^2 (Ixx 0.0224 -> "
                           "0.0226, Izz 0.0016 -> 0.0018) so that it is strictly inside the triangle inequality.")
            link = add_link("%s_%s" % (side, lname), mass, mirror_xyz(com) if mir else com,
                            mirror_inertia(inertia) if mir else inertia, (md, pr), comment)
            if lname == "foot":
                for end in ("toe", "heel"):
                    for lr in ("left", "right"):
                        link["collisions"].append({
                            "name": "%s_foot_contact_%s_%s" % (side, end, lr),
                            "xyz": (CONTACT_X[end], CONTACT_Y[lr], CONTACT_Z)})
        for (jname, parent, child, xyz, axis) in joint_defs:
            lo, hi = LIMITS_LEFT[jname]
            if mir and jname in MIRRORED_JOINTS:
                lo, hi = -hi, -lo
            joints.append({"name": "%s_%s" % (side, jname),
                           "parent": parent if parent == "torso" else "%s_%s" % (side, parent),
                           "child": "%s_%s" % (side, child), "xyz": mirror_xyz(xyz) if mir else xyz,
                           "axis": axis, "lower": lo, "upper": hi, "effort": EFFORT_NM[jname],
                           "velocity": VELOCITY_RADS[jname], "kind": jname})
    return links, joints, meshes


# ----------------------------------------------------------------------------------
# Writers
# ----------------------------------------------------------------------------------


def fnum(x, digits=6):
    s = ("%.*f" % (digits, x)).rstrip("0").rstrip(".")
    return "0" if s in ("-0", "", "-") else s


def fvec(v, digits=6):
    return " ".join(fnum(c, digits) for c in v)


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="\n") as f:
        f.write(text)
    os.replace(tmp, path)


def obj_text(name, material, mesh):
    # Normals are written once per distinct printed value.
    lines = ["# DRACO visual mesh '%s' (%s): generated by make_draco.py, do not edit." % (name, material),
             "# Link frame, metres; triangles counter-clockwise seen from outside; closed parts.",
             "o %s" % name]
    for p in mesh.positions:
        lines.append("v " + fvec(p, 5))
    nidx, nmap = {}, []
    nlines = []
    for n in mesh.normals:
        s = fvec(n, 4)
        if s not in nidx:
            nidx[s] = len(nidx) + 1
            nlines.append("vn " + s)
        nmap.append(nidx[s])
    lines.extend(nlines)
    for tri in mesh.triangles:
        lines.append("f " + " ".join("%d//%d" % (p + 1, nmap[n]) for p, n in tri))
    return "\n".join(lines) + "\n"


def urdf_text(links, joints):
    o = []
    w = o.append
    w('<?xml version="1.0"?>')
    w("<!--")
    w("  DRACO biped (lower body, 10 joints): GENERATED by robots/draco/make_draco.py; do not edit,")
    w("  edit the script and run it again (python3 robots/draco/make_draco.py).")
    w("")
    w("  From the project's DRACO facts sheet: the paper (Ahn, Kim, Bang, Paine, Sentis, \"Control")
    w("  of a High Performance Bipedal Robot using Viscoelastic Liquid Cooled Actuators\": 1.30 m,")
    w("  37 kg, ranges of motion 1.5/1.19/2.27/2.14/1.55 rad) and the published 2019 robot")
    w("  description (joint origins and axes, masses, CoMs, inertias, foot contact points, the")
    w("  real robot's joint limits). The paper wins where they disagree.")
    w("")
    w("  Conventions: SI units. Root link 'torso' (a floating base in simulation; no joint to the")
    w("  world here). All joints at 0 = standing straight with the feet flat; every link frame is")
    w("  then parallel to the torso frame (x forward, y left, z up). Ankle zero = foot flat: the")
    w("  2019 description's -pi/2 rotation of the ankle frame is removed and its ankle limits are")
    w("  shifted by -pi/2. Right leg = left leg mirrored in y (origins, CoMs, products of inertia")
    w("  with y; hip roll and yaw limits negated and swapped).")
    w("  Joint ranges (upper - lower) are exactly the paper's ranges of motion.")
    w("  Joint dynamics: damping and friction 0 here: the actuator (VLCA) model provides the")
    w("  drivetrain's damping and friction.")
    w("  Contact: four spheres of radius %g m per foot (the only collision geometry)." % CONTACT_RADIUS)
    w("  Visuals: procedural meshes (package://draco/meshes/) plus a few cylinders and a box.")
    w("-->")
    w('<robot name="draco">')
    for name, rgba in MATERIALS:
        w('  <material name="%s"><color rgba="%s"/></material>' % (name, fvec(rgba, 3)))
    rgba_of = dict(MATERIALS)

    def origin(xyz, rpy):
        return '<origin xyz="%s" rpy="%s"/>' % (fvec(xyz), fvec(rpy, 10))

    for link in links:
        w("")
        if link["comment"]:
            w("  <!-- %s -->" % link["comment"])
        w('  <link name="%s">' % link["name"])
        ixx, ixy, ixz, iyy, iyz, izz = link["inertia"]
        w("    <inertial>")
        w("      " + origin(link["com"], (0, 0, 0)))
        w('      <mass value="%s"/>' % fnum(link["mass"], 9))
        w('      <inertia ixx="%s" ixy="%s" ixz="%s" iyy="%s" iyz="%s" izz="%s"/>'
          % tuple(fnum(v, 9) for v in (ixx, ixy, ixz, iyy, iyz, izz)))
        w("    </inertial>")
        for v in link["visuals"]:
            g = v["geometry"]
            if g[0] == "mesh":
                geom = '<mesh filename="%smeshes/%s.obj"/>' % (PACKAGE, g[1])
            elif g[0] == "cylinder":
                geom = '<cylinder radius="%s" length="%s"/>' % (fnum(g[1]), fnum(g[2]))
            else:
                geom = '<box size="%s"/>' % fvec(g[1])
            w('    <visual name="%s">' % v["name"])
            w("      " + origin(v["xyz"], v["rpy"]))
            w("      <geometry>%s</geometry>" % geom)
            w('      <material name="%s"><color rgba="%s"/></material>' % (v["material"], fvec(rgba_of[v["material"]], 3)))
            w("    </visual>")
        for c in link["collisions"]:
            w('    <collision name="%s">' % c["name"])
            w("      " + origin(c["xyz"], (0, 0, 0)))
            w('      <geometry><sphere radius="%s"/></geometry>' % fnum(CONTACT_RADIUS))
            w("    </collision>")
        w("  </link>")
    for j in joints:
        w("")
        if j["kind"] == "ankle":
            w("  <!-- Ankle: 0 = foot flat (the 2019 description: pi/2). Real robot [0.733, 2.269] - pi/2 "
              "= [-0.838, 0.698], widened to the paper's 1.55 rad. -->")
        w('  <joint name="%s" type="revolute">' % j["name"])
        w('    <parent link="%s"/>' % j["parent"])
        w('    <child link="%s"/>' % j["child"])
        w("    " + origin(j["xyz"], (0, 0, 0)))
        w('    <axis xyz="%s"/>' % fvec(j["axis"]))
        w('    <limit lower="%s" upper="%s" effort="%s" velocity="%s"/>'
          % (fnum(j["lower"]), fnum(j["upper"]), fnum(j["effort"]), fnum(j["velocity"])))
        w('    <dynamics damping="0.0" friction="0.0"/>')
        w("  </joint>")
    w("</robot>")
    return "\n".join(o) + "\n"


def generate():
    links, joints, meshes = build_robot()
    os.makedirs(MESH_DIR, exist_ok=True)
    materials = {}
    for link in links:
        for v in link["visuals"]:
            if v["geometry"][0] == "mesh":
                materials[v["geometry"][1]] = v["material"]
    wanted = set()
    for name, mesh in meshes.items():
        fn = name + ".obj"
        wanted.add(fn)
        write_atomic(os.path.join(MESH_DIR, fn), obj_text(name, materials[name], mesh))
    for fn in sorted(os.listdir(MESH_DIR)):   # drop meshes of an earlier version of this script
        if fn.endswith(".obj") and fn not in wanted:
            os.remove(os.path.join(MESH_DIR, fn))
    write_atomic(URDF_PATH, urdf_text(links, joints))
    print("wrote %s and %d meshes in %s" % (os.path.relpath(URDF_PATH), len(meshes), os.path.relpath(MESH_DIR)))


# ----------------------------------------------------------------------------------
# Check (reads the files back; independent of the generator's data)
# ----------------------------------------------------------------------------------


def read_obj(path):
    vs, ns, fs = [], [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t or t[0].startswith("#"):
                continue
            if t[0] == "v":
                vs.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == "vn":
                ns.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == "f":
                if len(t) != 4:
                    raise ValueError("%s: a face that is not a triangle" % path)
                fs.append(tuple((int(c.split("//")[0]) - 1, int(c.split("//")[1]) - 1) for c in t[1:]))
    return vs, ns, fs


def check_obj(path):
    """Returns (vertices, triangles, list of problems)."""
    vs, ns, fs = read_obj(path)
    problems = []
    edges = {}
    for fi, f in enumerate(fs):
        idx = [c[0] for c in f]
        for a, b in ((idx[0], idx[1]), (idx[1], idx[2]), (idx[2], idx[0])):
            edges[(a, b)] = edges.get((a, b), 0) + 1
        p0, p1, p2 = (vs[i] for i in idx)
        fn = cross(vsub(p1, p0), vsub(p2, p0))
        area2 = norm(fn)
        if area2 < 1e-12:
            problems.append("degenerate triangle %d" % fi)
            continue
        fn = vmul(fn, 1 / area2)
        for c in f:
            if dot(fn, ns[c[1]]) <= 0.0:
                problems.append("triangle %d: vertex normal against the face" % fi)
                break
    bad_edges = [e for e, k in edges.items() if k != 1 or edges.get((e[1], e[0]), 0) != 1]
    if bad_edges:
        problems.append("%d edges not shared by exactly two oppositely wound triangles" % len(bad_edges))
    for n in ns:
        if abs(norm(n) - 1) > 1e-3:
            problems.append("normal not unit")
            break
    # connected components (by shared positions) must enclose positive volume
    parent = list(range(len(vs)))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for f in fs:
        a = find(f[0][0])
        for c in f[1:]:
            b = find(c[0])
            if a != b:
                parent[b] = a
    vol = {}
    for f in fs:
        p0, p1, p2 = (vs[c[0]] for c in f)
        r = find(f[0][0])
        vol[r] = vol.get(r, 0.0) + dot(p0, cross(p1, p2)) / 6
    if any(v <= 0 for v in vol.values()):
        problems.append("a part with non-positive volume (inward facing)")
    return vs, fs, problems, len(vol)


def sym_eigenvalues(m):
    """Eigenvalues of a symmetric 3x3 (Jacobi rotations)."""
    a = [list(r) for r in m]
    for _ in range(50):
        off = a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2
        if off < 1e-30:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if abs(a[p][q]) < 1e-300:
                continue
            theta = (a[q][q] - a[p][p]) / (2 * a[p][q])
            t = (1 if theta >= 0 else -1) / (abs(theta) + math.sqrt(theta * theta + 1))
            c = 1 / math.sqrt(t * t + 1)
            s = t * c
            for k in range(3):
                akp, akq = a[k][p], a[k][q]
                a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
            for k in range(3):
                apk, aqk = a[p][k], a[q][k]
                a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
    return sorted(a[i][i] for i in range(3))


def parse_floats(s):
    return tuple(float(x) for x in s.split())


def check():
    failures = []

    def need(cond, what):
        if not cond:
            failures.append(what)
        return cond

    root = ET.parse(URDF_PATH).getroot()
    need(root.get("name") == "draco", "robot name is draco")
    links = {l.get("name"): l for l in root.findall("link")}
    joints = root.findall("joint")
    expected_links = ["torso"] + ["%s_%s" % (s, n) for s in "lr"
                                  for n in ("hip_yaw_link", "hip_roll_link", "thigh", "shank", "foot")]
    need(sorted(links) == sorted(expected_links), "links are exactly %s" % expected_links)
    expected_joints = ["%s_%s" % (s, n) for s in "lr" for n in ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle")]
    need([j.get("name") for j in joints] == expected_joints, "joints are exactly %s" % expected_joints)

    # mass and inertias
    total = 0.0
    print("links (mass kg; principal moments kg m^2):")
    for name in expected_links:
        l = links[name]
        m = float(l.find("inertial/mass").get("value"))
        total += m
        I = l.find("inertial/inertia")
        g = {k: float(I.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        mat = ((g["ixx"], g["ixy"], g["ixz"]), (g["ixy"], g["iyy"], g["iyz"]), (g["ixz"], g["iyz"], g["izz"]))
        ev = sym_eigenvalues(mat)
        need(ev[0] > 0, "%s inertia positive definite" % name)
        need(ev[0] + ev[1] > ev[2] * (1 + 1e-9), "%s inertia strictly satisfies the triangle inequality" % name)
        print("  %-14s %7.3f   %.5f %.5f %.5f" % (name, m, ev[0], ev[1], ev[2]))
    print("total mass: %.6f kg (paper: %.1f)" % (total, PAPER_MASS_KG))
    need(abs(total - PAPER_MASS_KG) < 1e-9, "total mass 37 kg")

    # default-pose forward kinematics (all joints 0)
    frames = {"torso": (IDENTITY, (0.0, 0.0, 0.0))}
    for j in joints:
        R, p = frames[j.find("parent").get("link")]
        o = j.find("origin")
        xyz, rpy = parse_floats(o.get("xyz")), parse_floats(o.get("rpy", "0 0 0"))
        frames[j.find("child").get("link")] = (mat_mul(R, rpy_matrix(rpy)), vadd(p, mat_vec(R, xyz)))

    # joint ranges
    print("joints (lower, upper, range rad; effort N m; velocity rad/s):")
    for j in joints:
        lim = j.find("limit")
        lo, hi = float(lim.get("lower")), float(lim.get("upper"))
        kind = j.get("name")[2:]
        need(abs((hi - lo) - PAPER_ROM[kind]) < 1e-9, "%s range = paper's %g" % (j.get("name"), PAPER_ROM[kind]))
        need(lo <= 0 <= hi, "%s: 0 within the limits" % j.get("name"))
        print("  %-12s [%7.3f, %6.3f]  %.3f   %5g  %4g" % (j.get("name"), lo, hi, hi - lo,
                                                          float(lim.get("effort")), float(lim.get("velocity"))))

    # visual extent
    zmin, zmax = float("inf"), float("-inf")
    lowest_visual, highest_visual = "", ""
    mesh_stats = {}
    for name in expected_links:
        R, p = frames[name]
        for v in links[name].findall("visual"):
            o = v.find("origin")
            xyz = parse_floats(o.get("xyz")) if o is not None else (0.0, 0.0, 0.0)
            rpy = parse_floats(o.get("rpy", "0 0 0")) if o is not None else (0.0, 0.0, 0.0)
            Rv, pv = mat_mul(R, rpy_matrix(rpy)), vadd(p, mat_vec(R, xyz))
            g = v.find("geometry")[0]
            if g.tag == "mesh":
                fn = g.get("filename")
                need(fn.startswith(PACKAGE), "mesh URI %s is package://draco/..." % fn)
                path = os.path.join(HERE, fn[len(PACKAGE):])
                if path not in mesh_stats:
                    vs, fs, problems, parts = check_obj(path)
                    mesh_stats[path] = (len(vs), len(fs), os.path.getsize(path), parts)
                    for pr in problems:
                        failures.append("%s: %s" % (os.path.basename(path), pr))
                vs = read_obj(path)[0]
                zs = [pv[2] + dot(Rv[2], q) for q in vs]
                lo, hi = min(zs), max(zs)
            else:
                a = Rv[2]   # world z row: z = pv.z + a . q
                if g.tag == "cylinder":
                    r, L = float(g.get("radius")), float(g.get("length"))
                    ext = abs(a[2]) * L / 2 + r * math.sqrt(max(0.0, 1 - a[2] ** 2))
                elif g.tag == "box":
                    s = parse_floats(g.get("size"))
                    ext = sum(abs(a[k]) * s[k] / 2 for k in range(3))
                else:
                    ext = float(g.get("radius"))
                lo, hi = pv[2] - ext, pv[2] + ext
            if lo < zmin:
                zmin, lowest_visual = lo, "%s/%s" % (name, v.get("name"))
            if hi > zmax:
                zmax, highest_visual = hi, "%s/%s" % (name, v.get("name"))
    height = zmax - zmin
    print("default pose, visual geometry: top %.4f m (%s), bottom %.4f m (%s): height %.4f m (paper %.2f)"
          % (zmax, highest_visual, zmin, lowest_visual, height, PAPER_HEIGHT_M))
    need(abs(height - PAPER_HEIGHT_M) <= 0.01, "visual height 1.30 +- 0.01 m")

    # contact spheres
    sphere_bottoms = []
    for side in "lr":
        foot = links["%s_foot" % side]
        R, p = frames[foot.get("name")]
        cols = foot.findall("collision")
        need(len(cols) == 4, "%s_foot has 4 collision spheres" % side)
        print("%s_foot contact spheres (world, default pose):" % side)
        for c in cols:
            s = c.find("geometry/sphere")
            need(s is not None and abs(float(s.get("radius")) - CONTACT_RADIUS) < 1e-12,
                 "%s is a sphere of radius 0.03" % c.get("name"))
            q = vadd(p, mat_vec(R, parse_floats(c.find("origin").get("xyz"))))
            bottom = q[2] - float(s.get("radius"))
            sphere_bottoms.append(bottom)
            print("  %-26s centre (%7.4f, %7.4f, %7.4f)  lowest z %.4f" % (c.get("name"), q[0], q[1], q[2], bottom))
    for name in expected_links:
        if not name.endswith("_foot"):
            need(not links[name].findall("collision"), "no collision geometry on %s" % name)
    need(max(sphere_bottoms) - min(sphere_bottoms) < 1e-12, "feet flat: all sphere bottoms at one height")
    need(min(sphere_bottoms) <= zmin, "contact spheres are the lowest points")
    print("lowest sphere point %.4f m; lowest visual point %.4f m; height incl. spheres %.4f m"
          % (min(sphere_bottoms), zmin, zmax - min(min(sphere_bottoms), zmin)))
    ly, ry = frames["l_foot"][1][1], frames["r_foot"][1][1]
    print("feet %.3f m apart (ankle frames)" % (ly - ry))

    # meshes
    total_bytes = 0
    print("meshes (vertices, triangles, closed parts, bytes):")
    for path in sorted(mesh_stats):
        nv, nf, size, parts = mesh_stats[path]
        total_bytes += size
        print("  %-26s %5d %5d %3d %7d" % (os.path.basename(path), nv, nf, parts, size))
    print("  %d meshes, %d bytes (%.0f KB)" % (len(mesh_stats), total_bytes, total_bytes / 1024))
    need(total_bytes < 600 * 1024, "meshes under 600 KB")
    on_disk = sorted(f for f in os.listdir(MESH_DIR) if f.endswith(".obj"))
    need(on_disk == sorted(os.path.basename(p) for p in mesh_stats), "every mesh on disk is used")
    n_mesh = sum(1 for l in links.values() for v in l.findall("visual") if v.find("geometry")[0].tag == "mesh")
    n_prim = sum(1 for l in links.values() for v in l.findall("visual") if v.find("geometry")[0].tag != "mesh")
    print("visuals: %d meshes, %d primitives" % (n_mesh, n_prim))

    if failures:
        print("CHECK FAILED:")
        for f in failures:
            print("  - " + f)
        return 1
    print("check passed")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="only check the files on disk")
    args = ap.parse_args()
    if not args.check:
        generate()
    sys.exit(check())


if __name__ == "__main__":
    main()
