"""Shared fixtures of the dloam Python suite. CTest sets PYTHONPATH (the module of the build tree),
DLOAM_BINARY (the CLI) and DLOAM_KITTI_0005 (the shared drive); tests that need the drive skip
without it."""

import os
import subprocess

import pytest

SCANS = 12  # scans of the drive run by the CLI and from Python


@pytest.fixture(scope="session")
def kitti_0005():
    path = os.environ.get("DLOAM_KITTI_0005", "")
    if not path or not os.path.isfile(os.path.join(path, "velodyne", "000000.bin")):
        pytest.skip("the shared drive kitti-raw-0005 is not there (DLOAM_KITTI_0005)")
    return path


@pytest.fixture(scope="session")
def dloam_binary():
    path = os.environ.get("DLOAM_BINARY", "")
    if not path or not os.access(path, os.X_OK):
        pytest.skip("the dloam tool is not given (DLOAM_BINARY)")
    return path


@pytest.fixture(scope="session")
def cli_run(kitti_0005, dloam_binary, tmp_path_factory):
    """`dloam run` on the first SCANS scans of the drive with the shipped kitti-raw configuration."""
    out = tmp_path_factory.mktemp("cli-run")
    subprocess.run(
        [dloam_binary, "run", kitti_0005, "--out", str(out), "--config", "kitti-raw", "--count", str(SCANS)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return out
