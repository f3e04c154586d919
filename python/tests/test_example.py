"""examples/python/plot_trajectory.py runs a drive and writes its plot."""

import os
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

import pytest


def test_plot_trajectory_writes_a_plot(kitti_0005, tmp_path):
    source = os.environ.get("DLOAM_SOURCE_DIR", "")
    script = os.path.join(source, "examples", "python", "plot_trajectory.py")
    if not os.path.isfile(script):
        pytest.skip("the source tree is not given (DLOAM_SOURCE_DIR)")
    out = tmp_path / "trajectory.svg"
    subprocess.run(
        [sys.executable, script, kitti_0005, "--config", "kitti-raw", "--count", "8", "--out", str(out)],
        check=True,
        env=dict(os.environ),
    )
    root = ElementTree.parse(out).getroot()
    assert root.tag.endswith("svg")
    # The estimate and the ground truth, each a line of 8 points (or matplotlib's paths).
    polylines = [e for e in root.iter() if e.tag.endswith("polyline") or e.tag.endswith("path")]
    assert len(polylines) >= 2
