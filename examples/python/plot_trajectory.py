#!/usr/bin/env python3
"""Runs dloam on a drive and plots its trajectory from above, with the ground truth when the drive
has poses.txt.

    PYTHONPATH=<prefix>/lib/python3.11/dist-packages python3 examples/python/plot_trajectory.py \
        ../shared/data/kitti-raw-0005 --config kitti-raw --out trajectory.svg

Any input `dloam run` reads works (a KITTI / SemanticKITTI folder, PCD files, a pcap capture, a ROS
bag). The plot is drawn with matplotlib when it is installed (PNG, SVG or PDF by the file name),
else written as a plain SVG file by this script.
"""

import argparse
import sys

import numpy as np

import dloam


def run(path, config, count):
    sequence = dloam.read_sequence(path, config=config)
    pipeline = dloam.Pipeline(config)
    n = len(sequence) if count is None else min(count, len(sequence))
    total_ms = 0.0
    for i in range(n):
        result = pipeline.process(sequence[i])
        total_ms += result.times["total"]
        if (i + 1) % 20 == 0 or i + 1 == n:
            print(f"scan {i + 1}/{n}: {total_ms / (i + 1):.0f} ms per scan", file=sys.stderr)
    trajectory = pipeline.trajectory()  # K x 4 x 4 sensor poses, as `dloam run` writes them
    gt = sequence.poses[:n] if sequence.poses is not None else None
    return trajectory, gt


def anchored(poses):
    """Poses relative to the first one (both trajectories start at the origin)."""
    return np.linalg.inv(poses[0]) @ poses


def plot_matplotlib(out, estimate, gt, title):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 8))
    if gt is not None:
        ax.plot(gt[:, 0, 3], gt[:, 1, 3], color="0.6", lw=5, label="ground truth")
    ax.plot(estimate[:, 0, 3], estimate[:, 1, 3], color="tab:blue", lw=2, label="dloam")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title)
    ax.grid(True)
    ax.legend()
    fig.savefig(out, bbox_inches="tight")


def plot_svg(out, estimate, gt, title, size=640, margin=50):
    """A plain SVG line plot (equal axes) with no plotting library."""
    xy = [estimate[:, :2, 3]] + ([gt[:, :2, 3]] if gt is not None else [])
    lo = np.min([a.min(axis=0) for a in xy], axis=0)
    hi = np.max([a.max(axis=0) for a in xy], axis=0)
    span = max(float(np.max(hi - lo)), 1e-3)
    scale = (size - 2 * margin) / span

    def points(a):
        px = margin + (a[:, 0] - lo[0]) * scale
        py = size - margin - (a[:, 1] - lo[1]) * scale  # y up
        return " ".join(f"{x:.1f},{y:.1f}" for x, y in zip(px, py))

    lines = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}" font-family="sans-serif">',
        f'<rect width="{size}" height="{size}" fill="white"/>',
        f'<text x="{size / 2}" y="24" text-anchor="middle" font-size="15">{title}</text>',
        f'<rect x="{margin}" y="{margin}" width="{size - 2 * margin}" height="{size - 2 * margin}" '
        'fill="none" stroke="#ccc"/>',
    ]
    if gt is not None:
        lines.append(f'<polyline points="{points(xy[1])}" fill="none" stroke="#999" stroke-width="5"/>')
    lines.append(f'<polyline points="{points(xy[0])}" fill="none" stroke="#1f77b4" stroke-width="2"/>')
    lines.append(
        f'<text x="{margin}" y="{size - 15}" font-size="12">{span:.1f} m across; blue: dloam'
        + ("; grey: ground truth" if gt is not None else "")
        + "</text>"
    )
    lines.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("sequence", help="anything `dloam run` reads")
    parser.add_argument("--config", help="YAML file or shipped configuration name (e.g. kitti-raw)")
    parser.add_argument("--preset", default="HDL-64E", help="sensor preset (default HDL-64E)")
    parser.add_argument("--count", type=int, help="scans to run (default: all)")
    parser.add_argument("--out", default="trajectory.svg", help="plot file (default trajectory.svg)")
    args = parser.parse_args()

    config = dloam.load_config(preset=args.preset, path=args.config)
    estimate, gt = run(args.sequence, config, args.count)
    estimate = anchored(estimate)
    if gt is not None:
        gt = anchored(gt)
        errors = dloam.evaluate_odometry(gt, estimate)
        title = f"{len(estimate)} scans: ATE {errors['ate_m']:.3f} m"
    else:
        title = f"{len(estimate)} scans"
    try:
        plot_matplotlib(args.out, estimate, gt, title)
    except ImportError:
        if not args.out.endswith(".svg"):
            sys.exit(f"matplotlib is not installed: write an .svg instead of {args.out}")
        plot_svg(args.out, estimate, gt, title)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
