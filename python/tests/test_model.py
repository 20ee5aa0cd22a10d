"""The robot model (docs/python.md, "The robot model") on DRACO (floating), the leg rig
(fixed base, a prismatic rail), a toy biped of our own (data/toy_biped.urdf, floating:
revolute, prismatic, continuous, fixed and welded joints, axes off the link axes, full
inertias) and Simbody's Atlas example where Debian's simbody docs have it, at random
states:

(a) the tree kernel (engine="kernel") against Simbody's own operators (engine="simbody":
    calcM, calcResidualForceIgnoringConstraints, calcAccelerationIgnoringConstraints,
    calcFrameJacobian, the system mass centre): M, b, g, every frame's placement and
    Jacobian in the three reference frames, the CoM and its Jacobian, inverse and forward
    dynamics, to KERNEL_VS_SIMBODY relative;
(b) inverse against forward dynamics: M a + b = rnea(a), aba(rnea(a)) = a on both engines,
    and closed forms a wrong convention would break (the base's rows of g and M, the
    CoM Jacobian's base columns, b - g quadratic in v);
(c) Jacobians against central differences along q ⊕ (±h δv): the frame's position and its
    orientation's log map in each reference frame, and the CoM, to FINITE_DIFFERENCE
    relative; integrate and difference inverse to each other;
and the description and the errors.
"""
import gzip
import math
import os
import pathlib
import shutil
import tempfile
import unittest

import numpy as np
from scipy.spatial.transform import Rotation

import dmbd

HERE = pathlib.Path(__file__).resolve().parent
TOY = HERE / "data" / "toy_biped.urdf"
ATLAS_GZ = pathlib.Path("/usr/share/doc/simbody/examples/src/TaskSpaceControl-Atlas/models/atlas_v4_free_pelvis.urdf.gz")

# Relative to max(1, the largest entry of the reference): both engines are exact up to
# rounding (entries up to ~100 for M of DRACO, ~1000 for b at |v| = 2).
KERNEL_VS_SIMBODY = 1e-10
# Central differences with step H: truncation ~H² (1e-12) and rounding ~1e-16/H (1e-10).
H = 1e-6
FINITE_DIFFERENCE = 1e-7
FRAMES = (dmbd.ReferenceFrame.LOCAL, dmbd.ReferenceFrame.WORLD, dmbd.ReferenceFrame.LOCAL_WORLD_ALIGNED)


def rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b)))))


def random_state(robot, rng):
    """q within the joint limits (±π where none), a random base pose; |v| <= 2."""
    q = robot.neutral()
    lo, hi = robot.lower_position_limit, robot.upper_position_limit
    for i in range(robot.nq):
        if robot.base == "floating" and i < 7:
            continue
        a, b = (lo[i], hi[i]) if np.isfinite(lo[i]) and np.isfinite(hi[i]) else (-math.pi, math.pi)
        q[i] = rng.uniform(a, b)
    if robot.base == "floating":
        quat = rng.normal(size=4)
        q[:4] = quat / np.linalg.norm(quat)
        q[4:7] = rng.uniform(-1, 1, 3)
    return q, rng.uniform(-2, 2, robot.nv)


def log3(R):
    return Rotation.from_matrix(R).as_rotvec()


_ROBOTS = {}


def robot(name):
    """Loaded once per test run (DRACO takes ~10 ms)."""
    if name not in _ROBOTS:
        if name == "draco":
            _ROBOTS[name] = dmbd.load_robot("draco", base="floating")
        elif name == "leg_rig":
            _ROBOTS[name] = dmbd.load_robot("leg_rig")
        else:
            _ROBOTS[name] = dmbd.load_robot(TOY, base="floating")
    return _ROBOTS[name]


ROBOTS = ("draco", "leg_rig", "toy")


def worst_kernel_vs_simbody(r, rng, states):
    """The worst relative difference of each quantity over `states` random states."""
    worst = {}

    def note(key, a, b):
        worst[key] = max(worst.get(key, 0.0), rel(a, b))

    for _ in range(states):
        q, v = random_state(r, rng)
        a = rng.uniform(-3, 3, r.nv)
        tau = rng.uniform(-50, 50, r.nv)
        for name, f in (("M", lambda e: r.mass_matrix(q, engine=e)),
                        ("b", lambda e: r.bias_forces(q, v, engine=e)),
                        ("g", lambda e: r.gravity_forces(q, engine=e)),
                        ("com", lambda e: r.com(q, engine=e)),
                        ("J_com", lambda e: r.com_jacobian(q, engine=e)),
                        ("rnea", lambda e: r.inverse_dynamics(q, v, a, engine=e)),
                        ("aba", lambda e: r.forward_dynamics(q, v, tau, engine=e))):
            note(name, f("kernel"), f("simbody"))
        for frame in r.link_names:
            X, Xs = r.frame_placement(q, frame), r.frame_placement(q, frame, engine="simbody")
            note("placement", X.homogeneous, Xs.homogeneous)
            for rf in FRAMES:
                note("J " + rf.name, r.frame_jacobian(q, frame, rf), r.frame_jacobian(q, frame, rf, engine="simbody"))
    return worst


class KernelAgainstSimbody(unittest.TestCase):
    def check(self, r, label, states):
        worst = worst_kernel_vs_simbody(r, np.random.default_rng(3), states)
        print(f"\n{label}: kernel vs Simbody, worst relative: " + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()))
        for k, v in worst.items():
            self.assertLess(v, KERNEL_VS_SIMBODY, f"{label}: {k}")
        return worst

    def test_every_quantity_agrees_on_the_three_robots(self):
        for name in ROBOTS:
            with self.subTest(robot=name):
                self.check(robot(name), name, states=3)

    def test_atlas_agrees(self):
        if not ATLAS_GZ.exists():
            self.skipTest(f"{ATLAS_GZ} is absent (Debian's simbody docs)")
        folder = tempfile.mkdtemp(prefix="dmbd-atlas-")
        try:
            urdf = pathlib.Path(folder) / "atlas.urdf"
            with gzip.open(ATLAS_GZ) as src, open(urdf, "wb") as dst:
                shutil.copyfileobj(src, dst)
            atlas = dmbd.load_robot(urdf, base="floating")
        finally:
            shutil.rmtree(folder)
        self.assertEqual(atlas.nv, 6 + len(atlas.joint_names))
        self.check(atlas, "Atlas", states=1)


class InverseAgainstForward(unittest.TestCase):
    def test_rnea_and_aba_are_inverse_on_both_engines(self):
        rng = np.random.default_rng(5)
        worst = 0.0
        for name in ROBOTS:
            r = robot(name)
            for _ in range(3):
                q, v = random_state(r, rng)
                a = rng.uniform(-3, 3, r.nv)
                for engine in ("kernel", "simbody"):
                    tau = r.inverse_dynamics(q, v, a, engine=engine)
                    M, b = r.mass_matrix(q, engine=engine), r.bias_forces(q, v, engine=engine)
                    e1 = rel(M @ a + b, tau)
                    e2 = rel(r.forward_dynamics(q, v, tau, engine=engine), a)
                    worst = max(worst, e1, e2)
                    self.assertLess(e1, 1e-12, f"{name} {engine}: M a + b against rnea")
                    self.assertLess(e2, 1e-9, f"{name} {engine}: aba(rnea(a)) against a")
        print(f"\nrnea/aba round trip, worst relative {worst:.1e}")

    def test_closed_forms_of_the_base_and_the_velocity_terms(self):
        rng = np.random.default_rng(6)
        for name in ("draco", "toy"):
            r = robot(name)
            m, g0 = r.total_mass, r.gravity
            q, v = random_state(r, rng)
            c, p = r.com(q), q[4:7]
            weight = np.array([0.0, 0.0, m * g0])
            g = r.gravity_forces(q)
            # v = [angular velocity, origin velocity] in world: the base's linear rows of g
            # carry the weight, its angular rows the weight's moment about the base origin.
            np.testing.assert_allclose(g[3:6], weight, atol=1e-10 * m * g0)
            np.testing.assert_allclose(g[0:3], np.cross(c - p, weight), atol=1e-10 * m * g0)
            M = r.mass_matrix(q)
            np.testing.assert_allclose(M[3:6, 3:6], m * np.eye(3), atol=1e-12 * m)
            np.testing.assert_allclose(r.com_jacobian(q)[:, 3:6], np.eye(3), atol=1e-12)
            np.testing.assert_allclose(M, M.T, atol=1e-12 * np.abs(M).max())
            self.assertGreater(np.linalg.eigvalsh(M).min(), 0.0)
            # b(q, v) - g(q) is quadratic in v.
            np.testing.assert_allclose(r.bias_forces(q, 2 * v) - g, 4 * (r.bias_forces(q, v) - g),
                                       atol=1e-10 * np.abs(r.bias_forces(q, 2 * v)).max())
            np.testing.assert_allclose(r.bias_forces(q, np.zeros(r.nv)), g, atol=1e-12 * m * g0)


def finite_difference_twist(r, q, dv, frame, rf):
    """The frame's velocity along dv in reference frame rf, [linear; angular], by central
    differences of its placement at q ⊕ (±H dv)."""
    X0 = r.frame_placement(q, frame)
    Xp = r.frame_placement(r.integrate(q, H * dv), frame)
    Xm = r.frame_placement(r.integrate(q, -H * dv), frame)
    dp = (Xp.translation - Xm.translation) / (2 * H)
    w_world = log3(Xp.rotation @ Xm.rotation.T) / (2 * H)
    if rf == dmbd.ReferenceFrame.LOCAL:
        return np.concatenate([X0.rotation.T @ dp, log3(Xm.rotation.T @ Xp.rotation) / (2 * H)])
    if rf == dmbd.ReferenceFrame.WORLD:  # the body's point at the world origin
        return np.concatenate([dp - np.cross(w_world, X0.translation), w_world])
    return np.concatenate([dp, w_world])


class JacobiansAgainstFiniteDifferences(unittest.TestCase):
    def test_frame_and_com_jacobians(self):
        rng = np.random.default_rng(8)
        worst = {}
        for name in ROBOTS:
            r = robot(name)
            for _ in range(2):
                q, _ = random_state(r, rng)
                dv = rng.normal(size=r.nv)
                dv /= np.linalg.norm(dv)
                for frame in r.frame_names:
                    for rf in FRAMES:
                        fd = finite_difference_twist(r, q, dv, frame, rf)
                        e = rel(r.frame_jacobian(q, frame, rf) @ dv, fd)
                        worst[rf.name] = max(worst.get(rf.name, 0.0), e)
                        self.assertLess(e, FINITE_DIFFERENCE, f"{name} {frame} {rf.name}")
                fd = (r.com(r.integrate(q, H * dv)) - r.com(r.integrate(q, -H * dv))) / (2 * H)
                e = rel(r.com_jacobian(q) @ dv, fd)
                worst["com"] = max(worst.get("com", 0.0), e)
                self.assertLess(e, FINITE_DIFFERENCE, f"{name} CoM")
                self.assertGreater(np.linalg.norm(fd), 1e-3, f"{name}: the CoM moves along dv")
        print("\nJacobians vs central differences, worst relative: " + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()))

    def test_integrate_and_difference_are_inverse(self):
        rng = np.random.default_rng(9)
        for name in ROBOTS:
            r = robot(name)
            q0, _ = random_state(r, rng)
            v = rng.uniform(-1, 1, r.nv)  # base rotation under π
            q1 = r.integrate(q0, v)
            np.testing.assert_allclose(r.difference(q0, q1), v, atol=1e-12)
            np.testing.assert_allclose(r.integrate(q0, r.difference(q0, q1)), q1, atol=1e-12)
            n = 7 if r.base == "floating" else 0
            np.testing.assert_allclose(q1[n:], q0[n:] + v[r.nv - (r.nq - n):], atol=1e-15)
            if n:
                self.assertAlmostEqual(float(np.linalg.norm(q1[:4])), 1.0, places=14)
                np.testing.assert_allclose(q1[4:7], q0[4:7] + v[3:6], atol=1e-15)


class Description(unittest.TestCase):
    def test_draco(self):
        r = robot("draco")
        self.assertEqual((r.nq, r.nv, r.base, r.root_link), (17, 16, "floating", "torso"))
        self.assertEqual(len(r.joint_names), 10)
        knee = next(j for j in r.joints if j.name == "l_knee")
        self.assertEqual((knee.type, knee.q_index, knee.v_index), ("revolute", 7 + r.joint_names.index("l_knee"), 6 + r.joint_names.index("l_knee")))
        self.assertEqual(r.lower_position_limit[knee.q_index], knee.lower)
        self.assertEqual(r.effort_limit[knee.v_index], knee.effort_limit)
        self.assertTrue(np.all(np.isinf(r.velocity_limit[:6])))
        self.assertAlmostEqual(r.total_mass, sum(l.mass for l in r.links), places=12)
        q = r.neutral()
        np.testing.assert_array_equal(q[:4], [1, 0, 0, 0])
        # A joint's frame is its child link's.
        self.assertTrue(np.allclose(r.frame_placement(q, "l_knee").homogeneous, r.frame_placement(q, knee.child).homogeneous))

    def test_leg_rig(self):
        r = robot("leg_rig")
        self.assertEqual((r.nq, r.nv, r.base), (4, 4, "fixed"))
        self.assertEqual([j.type for j in r.joints if j.q_index is not None][0], "prismatic")

    def test_toy(self):
        r = robot("toy")
        kinds = {j.name: (j.type, j.q_index, j.welded) for j in r.joints}
        self.assertEqual(kinds["l_knee"], ("prismatic", 8, False))
        self.assertEqual(kinds["l_ankle"], ("continuous", 9, False))
        self.assertEqual(kinds["l_toe_joint"], ("fixed", None, False))
        self.assertEqual(kinds["antenna_slide"], ("prismatic", None, True))  # moves no mass
        ankle = next(j for j in r.joints if j.name == "l_ankle")
        self.assertEqual((ankle.lower, ankle.upper, ankle.velocity_limit, ankle.effort_limit), (-math.inf, math.inf, 12.0, 40.0))
        self.assertAlmostEqual(r.total_mass, 12.6, places=12)
        pelvis = r.links[0]
        self.assertEqual((pelvis.name, pelvis.parent_joint), ("pelvis", None))
        np.testing.assert_allclose(pelvis.com, [0.01, -0.02, 0.03])
        # The imu frame: 0.05 m ahead and 0.1 m above the pelvis, turned 90° about z.
        X = r.frame_placement(r.neutral(), "imu")
        np.testing.assert_allclose(X.translation, [0.05, 0, 0.1], atol=1e-15)
        np.testing.assert_allclose(X.rotation, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)


class Errors(unittest.TestCase):
    def assert_one_line(self, cls, pattern, f, *args, **kwargs):
        with self.assertRaisesRegex(cls, pattern) as c:
            f(*args, **kwargs)
        self.assertNotIn("\n", str(c.exception))
        return str(c.exception)

    def test_mistakes(self):
        r = robot("draco")
        q = r.neutral()
        self.assert_one_line(dmbd.InputError, r"robot 'draco' has no frame 'l_fot' .*closest: 'l_foot'", r.frame_placement, q, "l_fot")
        self.assert_one_line(dmbd.InputError, r"^q has 3 entries, expected nq = 17$", r.mass_matrix, [0, 0, 1])
        self.assert_one_line(dmbd.InputError, r"^v has 17 entries, expected nv = 16$", r.bias_forces, q, np.zeros(17))
        self.assert_one_line(dmbd.InputError, r"^tau has 2 entries", r.forward_dynamics, q, np.zeros(16), [1, 2])
        bad = q.copy()
        bad[8] = np.nan
        self.assert_one_line(dmbd.InputError, r"^q\[8\] is not finite$", r.com, bad)
        bad = q.copy()
        bad[:4] = 0
        self.assert_one_line(dmbd.InputError, r"quaternion .* is zero", r.com, bad)
        self.assert_one_line(dmbd.InputError, r"engine 'pinocchio'", r.mass_matrix, q, engine="pinocchio")
        self.assert_one_line(dmbd.InputError, r"reference_frame 'BODY'", r.frame_jacobian, q, "torso", "BODY")
        self.assert_one_line(dmbd.InputError, r"base 'free'", dmbd.load_robot, "draco", base="free")
        self.assert_one_line(dmbd.ModelError, r"robot 'drako' not found", dmbd.load_robot, "drako")
        self.assert_one_line(dmbd.ModelError, r"no_such\.urdf", dmbd.load_robot, "/nonexistent/no_such.urdf")
        with self.assertRaises(TypeError):
            r.mass_matrix(["a"] * 17)
        # A reference frame by name is accepted too.
        np.testing.assert_array_equal(r.frame_jacobian(q, "torso", "local"), r.frame_jacobian(q, "torso", dmbd.ReferenceFrame.LOCAL))

    def test_a_floating_joint_inside_the_tree_is_refused(self):
        text = TOY.read_text().replace('name="l_knee" type="prismatic"', 'name="l_knee" type="floating"')
        with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as f:
            f.write(text)
        try:
            self.assert_one_line(dmbd.ModelError, r"joint 'l_knee' is floating", dmbd.load_robot, f.name)
        finally:
            os.unlink(f.name)


if __name__ == "__main__":
    unittest.main()
