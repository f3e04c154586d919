"""dloam: LiDAR SLAM for dynamic scenes.

    import dloam
    config = dloam.load_config(preset="HDL-64E", path="kitti-raw")  # a file, or a shipped name
    pipeline = dloam.Pipeline(config)
    for scan in dloam.read_sequence("kitti-raw-0005"):
        result = pipeline.process(scan)       # or pipeline.process(points, times, stamp)
        print(result.pose[:3, 3], result.times["total"])
    poses = pipeline.trajectory()             # K x 4 x 4, the poses `dloam run` writes

See docs/python.md.
"""

from ._dloam import (  # noqa: F401
    Config,
    InputError,
    Pipeline,
    Result,
    Scan,
    Sequence,
    camera_to_lidar,
    data_dir,
    evaluate_mos,
    evaluate_odometry,
    has_simulator,
    lidar_to_camera,
    load_config,
    read_kitti_poses,
    read_sequence,
    run,
    sensor_presets,
    shipped_configs,
    write_kitti_poses,
)

if has_simulator:
    from ._dloam import Simulator  # noqa: F401

__version__ = "0.1.0"
