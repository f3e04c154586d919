"""The pipeline from Python gives the poses `dloam run` writes, scan for scan."""

import os

import numpy as np
import pytest

import dloam
from conftest import SCANS


def run_python(sequence, config, as_arrays):
    pipeline = dloam.Pipeline(config)
    results = []
    for i in range(SCANS):
        scan = sequence[i]
        if as_arrays:
            results.append(pipeline.process(scan.points, scan.times, scan.stamp))
        else:
            results.append(pipeline.process(scan))
    return pipeline, results


def written(poses, tmp_path, name):
    """The poses as a KITTI file holds them (10 significant digits), read back."""
    path = os.path.join(tmp_path, name)
    dloam.write_kitti_poses(path, poses)
    return dloam.read_kitti_poses(path)


@pytest.mark.parametrize("as_arrays", [False, True], ids=["scan", "arrays"])
def test_trajectory_equals_the_cli_poses(kitti_0005, cli_run, tmp_path, as_arrays):
    sequence = dloam.read_sequence(kitti_0005)
    config = dloam.load_config(path="kitti-raw")
    pipeline, results = run_python(sequence, config, as_arrays)
    trajectory = pipeline.trajectory()
    assert trajectory.shape == (SCANS, 4, 4)
    assert trajectory.dtype == np.float64

    cli = dloam.read_kitti_poses(str(cli_run / "poses.txt"))  # camera frame: the drive has calib.txt Tr
    assert cli.shape == (SCANS, 4, 4)
    tr = sequence.calib_tr
    assert tr is not None
    ours = dloam.lidar_to_camera(trajectory, tr)
    np.testing.assert_array_equal(written(ours, tmp_path, "python.txt"), cli)
    # The car moves: the comparison is not between two identity trajectories.
    assert np.linalg.norm(trajectory[-1][:3, 3]) > 1.0

    for i, r in enumerate(results):
        assert r.index == i
        assert r.pose.shape == (4, 4)
        assert r.labels.shape == (len(sequence[i]),)
        assert r.labels.dtype == np.uint32
        assert set(np.unique(r.labels & 0xFFFF)) <= {9, 251}  # class 9 static, 251 moving (instance ids above)
        assert r.times["total"] > 0.0
        # The real drive at 10 Hz: every step fits, the detection never sits a scan out.
        assert (r.lost, r.reinitialized, r.detection_suspended) == (False, False, False)
        assert set(r.times) >= {"segmentation", "detection", "features", "odometry", "mapping", "total"}


def test_run_writes_the_cli_outputs(kitti_0005, cli_run, tmp_path):
    out = tmp_path / "run"
    summary = dloam.run(kitti_0005, str(out), dloam.load_config(path="kitti-raw"), count=SCANS)
    assert summary["scans"] == SCANS
    for name in ("poses.txt", "poses_tum.txt", "map.ply", "timing.csv", "config.yaml", "metrics.json"):
        assert (out / name).is_file(), name
    np.testing.assert_array_equal(
        dloam.read_kitti_poses(str(out / "poses.txt")), dloam.read_kitti_poses(str(cli_run / "poses.txt"))
    )
    assert summary["trajectory"].shape == (SCANS, 4, 4)
    assert "odometry" in summary["metrics"]
    assert summary["metrics"]["tracking"]["scans"] == SCANS


def test_global_map_and_config_of_the_pipeline(kitti_0005):
    sequence = dloam.read_sequence(kitti_0005)
    pipeline = dloam.Pipeline(dloam.load_config(path="kitti-raw"))
    for i in range(SCANS):
        pipeline.process(sequence[i])
    world = pipeline.global_map()
    assert world.ndim == 2 and world.shape[1] == 3 and world.shape[0] > 1000
    assert pipeline.scans == SCANS
    assert pipeline.config.get("detection.detector") in ("geometric", "cnn")  # auto was resolved


def test_bad_points_are_refused():
    pipeline = dloam.Pipeline(dloam.load_config())
    with pytest.raises(ValueError, match="N x 3 or N x 4"):
        pipeline.process(np.zeros((10, 2)))
    points = np.zeros((10, 4), dtype=np.float32)
    points[3, 0] = np.nan
    with pytest.raises(dloam.InputError, match="point 3"):
        pipeline.process(points)
    with pytest.raises(ValueError, match="one time per point"):
        pipeline.process(np.ones((10, 4), dtype=np.float32), np.zeros(3, dtype=np.float32))
