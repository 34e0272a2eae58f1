import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.errors import InputError
from armkit.spatial.rotations import (
    CONVENTIONS,
    angular_velocity_matrix,
    axis_angle_from_matrix,
    euler_from_matrix,
    matrix_from_axis_angle,
    matrix_from_euler,
    matrix_from_quaternion_wxyz,
    parse_convention,
    quaternion_wxyz_from_matrix,
    rotation_angle_between,
)


def Rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def Ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def Rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


ELEMENTARY = {"x": Rx, "y": Ry, "z": Rz}
angle = st.floats(-np.pi, np.pi, allow_nan=False)


def test_there_are_24_conventions():
    assert len(CONVENTIONS) == 24 and len(set(CONVENTIONS)) == 24


@pytest.mark.parametrize("convention", CONVENTIONS)
@given(a1=angle, a2=angle, a3=angle)
@settings(max_examples=30, deadline=None)
def test_matrix_from_euler_is_the_named_product(convention, a1, a2, a3):
    conv = parse_convention(convention)
    factors = [ELEMENTARY[axis](a) for axis, a in zip(conv.axes, (a1, a2, a3), strict=True)]
    expected = factors[2] @ factors[1] @ factors[0] if conv.extrinsic else (
        factors[0] @ factors[1] @ factors[2])
    np.testing.assert_allclose(matrix_from_euler([a1, a2, a3], convention), expected, atol=1e-14)


@pytest.mark.parametrize("convention", CONVENTIONS)
@given(a1=angle, a2=angle, a3=angle)
@settings(max_examples=30, deadline=None)
def test_matrix_round_trips_through_every_convention(convention, a1, a2, a3):
    R = matrix_from_euler([a1, a2, a3], convention)
    angles = euler_from_matrix(R, convention)
    assert np.all(np.isfinite(angles))
    assert rotation_angle_between(matrix_from_euler(angles, convention), R) < 1e-12


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("lock", [0, 1])
@given(a1=angle, a3=angle)
@settings(max_examples=15, deadline=None)
def test_gimbal_lock_sets_third_angle_to_zero_and_round_trips(convention, lock, a1, a3):
    conv = parse_convention(convention)
    proper = conv.axes[0] == conv.axes[2]
    middle = (0.0, np.pi)[lock] if proper else (np.pi / 2, -np.pi / 2)[lock]
    R = matrix_from_euler([a1, middle, a3], convention)
    angles = euler_from_matrix(R, convention)
    assert np.all(np.isfinite(angles))
    assert angles[2] == 0.0
    assert rotation_angle_between(matrix_from_euler(angles, convention), R) < 1e-9


def test_seed_rpy_at_gimbal_lock_is_deterministic():
    # report 000: pitch -pi/2 leaves only roll + yaw defined; armkit puts it all in roll.
    R = matrix_from_euler([np.pi / 2, -np.pi / 2, 0.0], "xyz-fixed")
    np.testing.assert_allclose(euler_from_matrix(R, "rpy"), [np.pi / 2, -np.pi / 2, 0.0], atol=1e-9)


def test_degrees_flag_and_aliases():
    R = matrix_from_euler([90, 0, 0], "roll-pitch-yaw", degrees=True)
    np.testing.assert_allclose(R, Rx(np.pi / 2), atol=1e-15)
    np.testing.assert_allclose(euler_from_matrix(R, "xyz-fixed", degrees=True), [90, 0, 0], atol=1e-12)


def test_batches_equal_one_at_a_time():
    rng = np.random.default_rng(0)
    angles = rng.uniform(-np.pi, np.pi, (2, 5, 3))
    R = matrix_from_euler(angles, "zyz-euler")
    assert R.shape == (2, 5, 3, 3)
    for idx in np.ndindex(2, 5):
        np.testing.assert_array_equal(R[idx], matrix_from_euler(angles[idx], "zyz-euler"))
    back = euler_from_matrix(R, "zyz-euler")
    assert back.shape == (2, 5, 3)
    T = np.tile(np.eye(4), (2, 5, 1, 1))
    T[..., :3, :3] = R
    np.testing.assert_array_equal(euler_from_matrix(T, "zyz-euler"), back)


@given(a1=angle, a2=angle, a3=angle)
@settings(max_examples=50, deadline=None)
def test_quaternion_and_axis_angle_round_trip(a1, a2, a3):
    R = matrix_from_euler([a1, a2, a3], "xyz-euler")
    q = quaternion_wxyz_from_matrix(R)
    assert q[0] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-14
    assert rotation_angle_between(matrix_from_quaternion_wxyz(q), R) < 1e-12
    assert rotation_angle_between(matrix_from_axis_angle(axis_angle_from_matrix(R)), R) < 1e-12


def test_quaternion_is_scalar_first():
    q = quaternion_wxyz_from_matrix(Rz(np.pi / 2))
    np.testing.assert_allclose(q, [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)], atol=1e-15)


@pytest.mark.parametrize("convention", ["xyz-fixed", "xyz-euler", "zyz-euler", "zxy-fixed"])
def test_angular_velocity_matrix_matches_finite_differences(convention):
    rng = np.random.default_rng(1)
    angles = rng.uniform(-1, 1, 3)
    rates = rng.normal(size=3)
    h = 1e-6
    R_plus = matrix_from_euler(angles + h * rates, convention)
    R_minus = matrix_from_euler(angles - h * rates, convention)
    R_dot = (R_plus - R_minus) / (2 * h)
    W = R_dot @ matrix_from_euler(angles, convention).T
    omega = np.array([W[2, 1], W[0, 2], W[1, 0]])
    np.testing.assert_allclose(angular_velocity_matrix(angles, convention) @ rates, omega, atol=1e-8)


def test_rotation_angle_between_is_accurate_for_tiny_angles():
    assert rotation_angle_between(np.eye(3), Rz(1e-12)) == pytest.approx(1e-12, rel=1e-6)
    assert rotation_angle_between(np.eye(3), Rz(np.pi)) == pytest.approx(np.pi)


@pytest.mark.parametrize("bad", ["xyz", "xxy-fixed", "abc-euler", "xyz-intrinsic", ""])
def test_unknown_convention_is_named(bad):
    with pytest.raises(InputError, match="unknown angle convention .*expected one of"):
        parse_convention(bad)


def test_bad_values_are_rejected():
    with pytest.raises(InputError, match="NaN"):
        matrix_from_euler([np.nan, 0, 0])
    with pytest.raises(InputError, match=r"expected shape \(\.\.\., 3\)"):
        matrix_from_euler([0, 0])
    with pytest.raises(InputError, match="expected numbers"):
        matrix_from_euler(["a", 0, 0])
    with pytest.raises(InputError, match="non-zero quaternion"):
        matrix_from_quaternion_wxyz([0, 0, 0, 0])
    with pytest.raises(InputError, match=r"expected shape \(\.\.\., 3, 3\)"):
        euler_from_matrix(np.eye(2))


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_agrees_with_scipy_away_from_gimbal_lock(convention):
    from scipy.spatial.transform import Rotation

    conv = parse_convention(convention)
    R = Rotation.random(200, random_state=3).as_matrix()
    ours = euler_from_matrix(R, convention)
    theirs = Rotation.from_matrix(R).as_euler(conv.axes if conv.extrinsic else conv.axes.upper())
    lock = np.pi / 2 if conv.axes[0] != conv.axes[2] else 0.0
    away = np.abs(np.abs(theirs[:, 1]) - lock) > 1e-3
    wrapped = (ours - theirs + np.pi) % (2 * np.pi) - np.pi
    np.testing.assert_allclose(wrapped[away], 0.0, atol=1e-12)


def test_quaternions_and_rotation_vectors_agree_with_scipy():
    """armkit's own conversions (no scipy.spatial at import) against SciPy's, near the
    identity and near half turns included."""
    from scipy.spatial.transform import Rotation

    rotations = Rotation.concatenate([
        Rotation.random(2000, random_state=4),
        Rotation.from_rotvec(np.random.default_rng(5).normal(size=(200, 3)) * 1e-9),
        Rotation.from_rotvec(np.random.default_rng(6).normal(size=(200, 3)) * 0 + [np.pi - 1e-9, 0, 0]),
    ])
    R = rotations.as_matrix()
    expected = rotations.as_quat(scalar_first=True)
    expected = np.where(expected[:, :1] < 0, -expected, expected)
    np.testing.assert_allclose(quaternion_wxyz_from_matrix(R), expected, rtol=0, atol=1e-15 * 4)
    np.testing.assert_allclose(matrix_from_quaternion_wxyz(expected), R, rtol=0, atol=1e-15 * 4)
    rotvec = rotations.as_rotvec()
    np.testing.assert_allclose(matrix_from_axis_angle(rotvec), R, rtol=0, atol=1e-15 * 4)
    ours = axis_angle_from_matrix(R)
    # at (nearly) a half turn the axis may come out either way: the same rotation
    np.testing.assert_allclose(matrix_from_axis_angle(ours), R, rtol=0, atol=1e-15 * 4)
    away = np.linalg.norm(rotvec, axis=1) < 3.0
    np.testing.assert_allclose(ours[away], rotvec[away], rtol=0, atol=1e-14)
