"""read_sequence over the drive, the evaluators and the simulator."""

import numpy as np
import pytest

import dloam


def test_read_sequence_gives_kitti_scans(kitti_0005):
    sequence = dloam.read_sequence(kitti_0005)
    assert len(sequence) == 100
    scan = sequence[0]
    assert scan.points.dtype == np.float32
    assert scan.points.ndim == 2 and scan.points.shape[1] == 4 and scan.points.shape[0] > 100000
    raw = np.fromfile(f"{kitti_0005}/velodyne/000000.bin", dtype=np.float32).reshape(-1, 4)
    np.testing.assert_array_equal(scan.points, raw)
    assert scan.times is None  # KITTI .bin scans carry no per-point time
    assert scan.stamp is not None
    assert scan.labels is not None and scan.labels.shape == (scan.points.shape[0],)
    assert sequence[-1].index == 99
    assert sequence.poses.shape == (100, 4, 4)
    assert sum(1 for _ in sequence) == 100  # iteration ends (IndexError) after the last scan
    with pytest.raises(IndexError):
        sequence[100]


def test_read_sequence_errors_name_the_path(tmp_path):
    with pytest.raises(dloam.InputError, match="nothing-here"):
        dloam.read_sequence(str(tmp_path / "nothing-here"))


def test_evaluate_odometry_against_itself_and_a_drift(kitti_0005):
    gt = dloam.read_sequence(kitti_0005).poses
    same = dloam.evaluate_odometry(gt, gt)
    assert same["frames"] == 100
    assert same["t_rel_pct"] == pytest.approx(0.0, abs=1e-9)
    drift = gt.copy()
    drift[:, 0, 3] *= 1.02  # 2 % too long along x
    worse = dloam.evaluate_odometry(gt, drift)
    assert worse["t_rel_pct"] > 0.5
    assert worse["ate_m"] > same["ate_m"]
    with pytest.raises(dloam.InputError):
        dloam.evaluate_odometry(gt, gt[:10])


def test_evaluate_mos():
    gt = [np.array([9, 9, 251, 251], dtype=np.uint32)]
    perfect = dloam.evaluate_mos(gt, [gt[0].copy()])
    assert perfect["iou"] == pytest.approx(1.0)
    half = dloam.evaluate_mos(gt, [np.array([9, 9, 251, 9], dtype=np.uint32)])
    assert half["iou"] == pytest.approx(0.5)
    with pytest.raises(dloam.InputError):
        dloam.evaluate_mos(gt, [])


@pytest.mark.skipif(not dloam.has_simulator, reason="built without the simulator")
def test_simulator_frames_carry_ground_truth():
    simulator = dloam.Simulator("urban", frames=3, seed=2, config=dloam.load_config(preset="VLP-16"))
    assert len(simulator) == 3
    frame = simulator[1]
    assert frame.points.shape[1] == 4 and frame.points.shape[0] > 1000
    assert frame.times is not None and frame.times.shape == (frame.points.shape[0],)
    assert frame.labels.shape == (frame.points.shape[0],)
    assert frame.pose.shape == (4, 4)
    again = dloam.Simulator("urban", frames=3, seed=2, config=dloam.load_config(preset="VLP-16"))[1]
    np.testing.assert_array_equal(again.points, frame.points)  # deterministic
    with pytest.raises(dloam.InputError, match="frames"):
        dloam.Simulator("urban", frames=0)
    with pytest.raises(dloam.InputError):
        dloam.Simulator("moon")
