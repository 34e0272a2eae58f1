import numpy as np
import pytest
from conftest import assert_transform_close

from armkit.errors import InputError
from armkit.spatial.rotations import CONVENTIONS, matrix_from_euler
from armkit.spatial.transforms import (
    check_transform,
    invert_transform,
    pose_from_transform,
    rot_x,
    rot_z,
    trans_x,
    trans_z,
    transform_from,
    transform_from_pose,
)


def test_elementary_transforms():
    np.testing.assert_allclose(rot_z(np.pi / 2)[:3, :3] @ [1, 0, 0], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(rot_x(np.pi / 2)[:3, :3] @ [0, 1, 0], [0, 0, 1], atol=1e-15)
    assert trans_x(2.0)[0, 3] == 2.0 and trans_z(3.0)[2, 3] == 3.0
    assert rot_z(np.zeros((2, 3))).shape == (2, 3, 4, 4)


def test_invert_transform_batch():
    rng = np.random.default_rng(0)
    T = transform_from(matrix_from_euler(rng.uniform(-3, 3, (5, 3)), "zyz-euler"), rng.normal(size=(5, 3)))
    assert_transform_close(T @ invert_transform(T), np.tile(np.eye(4), (5, 1, 1)), 1e-14, 1e-14)


def test_check_transform_accepts_rigid_and_names_problems():
    T = transform_from(matrix_from_euler([0.1, 0.2, 0.3], "xyz-fixed"), [1, 2, 3])
    np.testing.assert_array_equal(check_transform(T), T)  # a rigid transform comes back unchanged
    with pytest.raises(InputError, match=r"expected shape \(\.\.\., 4, 4\)"):
        check_transform(np.eye(3))
    with pytest.raises(InputError, match="NaN"):
        check_transform(np.full((4, 4), np.nan))
    bad = T.copy()
    bad[3, 0] = 1
    with pytest.raises(InputError, match="last row"):
        check_transform(bad)
    scaled = T.copy()
    scaled[:3, :3] *= 2
    with pytest.raises(InputError, match="not a rotation matrix"):
        check_transform(scaled, "target")
    mirrored = T.copy()
    mirrored[:3, 0] *= -1
    with pytest.raises(InputError, match="det R = -1"):
        check_transform(mirrored)
    with pytest.raises(InputError, match="4x4 numeric"):
        check_transform([["a"] * 4] * 4)


def test_check_transform_projects_a_rounded_rotation_onto_the_nearest_one():
    T = transform_from(matrix_from_euler([0.3, -0.7, 1.1], "xyz-fixed"), [0.1, 0.2, 0.3])
    rounded = np.round(T, 6)
    fixed = check_transform(np.stack([rounded, T]))
    R = fixed[0, :3, :3]
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-15)
    assert np.abs(fixed[0] - rounded).max() < 2e-6
    np.testing.assert_array_equal(fixed[1], T)  # an exact one is left alone


@pytest.mark.parametrize("convention", sorted(CONVENTIONS))
@pytest.mark.parametrize("degrees", [False, True])
def test_pose_transform_round_trip(convention, degrees):
    rng = np.random.default_rng(7)
    T = transform_from(matrix_from_euler(rng.uniform(-3, 3, (20, 3)), "zyz-euler"), rng.normal(size=(20, 3)))
    pose = pose_from_transform(T, convention, degrees)
    assert pose.shape == (20, 6)
    np.testing.assert_array_equal(pose[:, :3], T[:, :3, 3])
    assert_transform_close(transform_from_pose(pose, convention, degrees), T, 1e-15, 1e-12)


def test_transform_from_pose_degrees_and_errors():
    T = transform_from_pose([0.1, 0.0, 0.2, 90.0, 0.0, 0.0], "xyz-fixed", degrees=True)
    assert_transform_close(T, transform_from(rot_x(np.pi / 2)[:3, :3], [0.1, 0.0, 0.2]), 0.0, 1e-15)
    with pytest.raises(InputError, match=r"expected 6 values \(x y z a b c\), got shape \(5,\)"):
        transform_from_pose([0, 0, 0, 0, 0])
    with pytest.raises(InputError, match="NaN or infinite"):
        transform_from_pose([0, 0, 0, 0, 0, np.nan])
