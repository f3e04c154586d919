#!/usr/bin/env bash
# Builds the libFuzzer harnesses of every reader (fuzz/, clang with ASan + UBSan) and runs each one
# for SECONDS (default 40), DLOAM_FUZZ_JOBS (default 2) at a time, with a timeout per input and a
# memory limit: the default run of the 20 harnesses takes about 7 minutes on 2 cores.
# DLOAM_FUZZ_BUILD_DIR (default build-fuzz) names the build tree; a tree already configured with
# -DDLOAM_BUILD_FUZZERS=ON (clang) is used as it is.
# Seed corpora are made here from ../shared/data (small cuts of its scans, captures, bags and
# calibration files; nothing is copied into the repository) and the repository's config/*.yaml; the
# corpora grow in build-fuzz/fuzz-corpus/ from run to run. Exits non-zero when any harness finds a
# crash, a leak, a timeout or an out-of-memory input; the reproducer is left in
# build-fuzz/fuzz-artifacts/<harness>/.
#   bash scripts/fuzz.sh [SECONDS] [HARNESS...]      e.g. bash scripts/fuzz.sh 600 pcd ply
# Reproduce one input: build-fuzz/fuzz/fuzz_pcd build-fuzz/fuzz-artifacts/pcd/crash-...
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_HARNESS=${1:-40}
shift || true
BUILD=${DLOAM_FUZZ_BUILD_DIR:-build-fuzz}
DATA=${DLOAM_SHARED_DATA:-../shared/data}
KITTI=$DATA/kitti-raw-0005
SENSORS=$DATA/sensors
JOBS=${DLOAM_FUZZ_JOBS:-2}

mkdir -p "$BUILD"
if grep -qs '^DLOAM_BUILD_FUZZERS:BOOL=ON' "$BUILD/CMakeCache.txt"; then
  # A tree configured with the harnesses (e.g. CI's sanitizer build, which also holds the tests).
  echo "== building the fuzz harnesses in $BUILD (configured there)"
else
  echo "== building the fuzz harnesses ($BUILD, clang, ASan + UBSan + libFuzzer)"
  launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
    -DCMAKE_CXX_COMPILER=clang++ "${launcher[@]}" -DDLOAM_BUILD_FUZZERS=ON -DDLOAM_BUILD_TESTS=OFF \
    -DDLOAM_BUILD_BENCH=OFF -DDLOAM_WITH_TORCH=OFF >"$BUILD/configure.log" 2>&1 || {
    cat "$BUILD/configure.log"
    exit 1
  }
fi
targets=(fuzzers)
grep -q '^DLOAM_WITH_ROS:BOOL=ON' "$BUILD/CMakeCache.txt" && targets+=(make_bag_seed)
cmake --build "$BUILD" -j"$JOBS" --target "${targets[@]}"

corpus=$BUILD/fuzz-corpus
mkdir -p "$corpus"
seed() {  # seed NAME FILE: copies FILE into NAME's corpus when it exists
  mkdir -p "$corpus/$1"
  [[ -f "$2" ]] && cp "$2" "$corpus/$1/seed-$(basename "$2")" || true
}

echo "== seed corpora from $DATA"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if [[ -d "$KITTI" ]]; then
  for s in 000000 000050; do
    head -c 4096 "$KITTI/velodyne/$s.bin" >"$tmp/$s.bin" && seed kitti_bin "$tmp/$s.bin"
    head -c 1024 "$KITTI/labels/$s.label" >"$tmp/$s.label" && seed labels "$tmp/$s.label"
  done
  head -n 20 "$KITTI/poses.txt" >"$tmp/poses.txt" && seed kitti_poses "$tmp/poses.txt"
  head -n 20 "$KITTI/times.txt" >"$tmp/times.txt" && seed times "$tmp/times.txt"
  paste -d' ' <(head -n 20 "$KITTI/times.txt") <(head -n 20 "$KITTI/poses.txt") |
    awk '{print $1, $5, $9, $13, 0, 0, 0, 1}' >"$tmp/tum.txt" && seed tum_poses "$tmp/tum.txt"
  seed calib "$KITTI/calib.txt"
  sed 's/^Tr:/Tr_velo_to_cam:/' "$KITTI/calib.txt" >"$tmp/calib_object.txt" && seed calib "$tmp/calib_object.txt"
  # PCD and PLY, ascii and binary, from the first 64 points of a scan.
  /usr/bin/python3 - "$KITTI/velodyne/000000.bin" "$tmp" <<'PY'
import struct, sys
raw = open(sys.argv[1], 'rb').read(64 * 16)
pts = [struct.unpack_from('<4f', raw, 16 * i) for i in range(len(raw) // 16)]
n, out = len(pts), sys.argv[2]
head = ('VERSION 0.7\nFIELDS x y z intensity t\nSIZE 4 4 4 4 4\nTYPE F F F F F\nCOUNT 1 1 1 1 1\n'
        'WIDTH %d\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\n' % (n, n))
rows = [p + (i / n,) for i, p in enumerate(pts)]
open(out + '/a.pcd', 'w').write(head + 'DATA ascii\n' + ''.join('%g %g %g %g %g\n' % r for r in rows))
open(out + '/b.pcd', 'wb').write((head + 'DATA binary\n').encode() + b''.join(struct.pack('<5f', *r) for r in rows))
org = head.replace('WIDTH %d\nHEIGHT 1' % n, 'WIDTH %d\nHEIGHT 2' % (n // 2))
nan = [r if i % 5 else (float('nan'),) * 3 + r[3:] for i, r in enumerate(rows)]
open(out + '/o.pcd', 'w').write(org + 'DATA ascii\n' + ''.join('%g %g %g %g %g\n' % r for r in nan))
ply = ('ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
       'property float intensity\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n')
open(out + '/a.ply', 'w').write(ply % ('ascii', n) + ''.join('%g %g %g %g 1 2 3\n' % p for p in pts))
open(out + '/b.ply', 'wb').write((ply % ('binary_little_endian', n)).encode() +
                                 b''.join(struct.pack('<4f3B', *p, 1, 2, 3) for p in pts))
PY
  for f in a.pcd b.pcd o.pcd; do seed pcd "$tmp/$f"; done
  for f in a.ply b.ply; do seed ply "$tmp/$f"; done
  if [[ -x "$BUILD/fuzz/make_bag_seed" ]]; then
    "$BUILD/fuzz/make_bag_seed" "$KITTI/velodyne/000000.bin" "$tmp/seed.bag" 48 && seed rosbag "$tmp/seed.bag"
  fi
fi
# Real PCD files of other sensors: their headers, cut to a few points.
for f in $(find "$DATA/sensors" -name '*.pcd' 2>/dev/null | sort | head -n 4); do
  /usr/bin/python3 - "$f" "$tmp/$(basename "$f")" <<'PY'
import sys
data = open(sys.argv[1], 'rb').read()
marker = b'DATA binary\n'
if marker in data:
    end = data.index(marker) + len(marker)
    keys = {l.split()[0]: l.split()[1:] for l in data[:end].decode().splitlines() if l and not l.startswith('#')}
    counts = keys.get('COUNT', ['1'] * len(keys['SIZE']))
    record = sum(int(s) * int(c) for s, c in zip(keys['SIZE'], counts))
    lines = []
    for l in data[:end].decode().splitlines():
        key = l.split()[0] if l.split() else ''
        lines.append({'WIDTH': 'WIDTH 32', 'HEIGHT': 'HEIGHT 1', 'POINTS': 'POINTS 32'}.get(key, l))
    open(sys.argv[2], 'wb').write(('\n'.join(lines) + '\n').encode() + data[end:end + 32 * record])
PY
  seed pcd "$tmp/$(basename "$f")"
done
for f in config/*.yaml; do seed config_yaml "$f"; done

# ROS 2 bags, CDR messages, captures, packets and the drivers' calibration files.
seeds=$BUILD/fuzz/make_seeds
if [[ -f "$KITTI/velodyne/000000.bin" ]]; then
  mkdir -p "$tmp/clouds"
  "$seeds" clouds "$KITTI/velodyne/000000.bin" "$tmp/clouds"
  for f in "$tmp"/clouds/*.cdr; do seed pointcloud2_cdr "$f"; done
  for f in "$tmp"/clouds/*.mcap; do seed mcap "$f"; done
  seed rosbag2_db3 "$tmp/clouds/cloud.db3"
  sed 's/[^ ]*_0\.db3/bag_0.db3/' "$tmp/clouds/metadata.yaml" >"$tmp/metadata.yaml" && seed rosbag2_metadata "$tmp/metadata.yaml"
fi
if [[ -d "$SENSORS" ]]; then
  # The first records of each capture (classic pcap: 24-byte file header, 16-byte record headers).
  for f in $(find "$SENSORS" -name '*.pcap' | sort); do
    out="$tmp/$(basename "$f" .pcap)-head.pcap"
    /usr/bin/python3 - "$f" "$out" <<'PY'
import struct, sys
data = open(sys.argv[1], 'rb').read()
if data[:4] in (b'\xd4\xc3\xb2\xa1', b'\x4d\x3c\xb2\xa1'):
    end, records = 24, 0
    while end + 16 <= len(data) and records < 6 and end < 40000:
        end += 16 + struct.unpack_from('<I', data, end + 8)[0]
        records += 1
    data = data[:end]
else:
    data = data[:16384]
open(sys.argv[2], 'wb').write(data)
PY
    seed pcap "$out"
  done
  for f in velodyne/rust-lidar-utils/velodyne_vlp16.pcap velodyne/rust-lidar-utils/hdl32_example.pcap \
    velodyne/rust-lidar-utils/velodyne_vlp32.pcap ouster/OS-0-32-U1_v2.2.0_1024x10-single-packet.pcap \
    ouster/OS-1-32-G_v2.1.1_1024x10.pcap; do
    [[ -f "$SENSORS/$f" ]] || continue
    out="$tmp/$(basename "$f" .pcap).packets"
    "$seeds" packets "$SENSORS/$f" "$out" 6 && seed packets "$out"
  done
  for f in $(find "$SENSORS" -name metadata.yaml | sort); do
    sed 's/[^ ]*_0\.db3/bag_0.db3/' "$f" >"$tmp/metadata-$(basename "$(dirname "$f")").yaml"
    seed rosbag2_metadata "$tmp/metadata-$(basename "$(dirname "$f")").yaml"
  done
  mkdir -p "$tmp/messages"
  for d in $(find "$SENSORS" -name metadata.yaml | sort); do
    for db3 in "$(dirname "$d")"/*.db3; do "$seeds" messages "$db3" "$tmp/messages" || true; done
  done
  for f in "$tmp"/messages/*.msg; do [[ -f "$f" ]] && head -c 65536 "$f" >"$f.cut" && seed packet_messages "$f.cut"; done
  for f in "$tmp"/messages/*.packets; do [[ -f "$f" ]] && seed packets "$f"; done
  for f in "$SENSORS"/hesai/nebula/calibration/*.csv; do seed hesai_calibration "$f"; done
  for f in "$SENSORS"/velodyne/nebula/calibration/*.yaml "$SENSORS"/velodyne/veloview/*.xml; do
    seed velodyne_calibration "$f"
  done
  for f in $(find "$SENSORS/ouster" -name '*.json' ! -name '*digest*' | sort); do seed ouster_metadata "$f"; done
fi
export DLOAM_FUZZ_OUSTER_METADATA=$SENSORS/ouster/OS-1-32-G_v2.1.1_1024x10.json

harnesses=("$@")
if ((${#harnesses[@]} == 0)); then
  for f in "$BUILD"/fuzz/fuzz_*; do [[ -x "$f" ]] && harnesses+=("$(basename "$f" | sed 's/^fuzz_//')"); done
fi
mkdir -p "$BUILD/fuzz-artifacts" "$BUILD/fuzz-logs"
run_one() {  # run_one NAME: runs one harness, leaves its exit status in fuzz-logs/NAME.status
  local h=$1 log=$BUILD/fuzz-logs/$1.log status=0
  mkdir -p "$corpus/$h" "$BUILD/fuzz-artifacts/$h"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$BUILD/fuzz/fuzz_$h" -max_total_time="$SECONDS_PER_HARNESS" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$BUILD/fuzz-artifacts/$h/" "$corpus/$h" \
    >"$log" 2>&1 || status=$?
  echo "$status" >"$BUILD/fuzz-logs/$h.status"
}
echo "== running ${#harnesses[@]} harnesses for ${SECONDS_PER_HARNESS} s each, $JOBS at a time"
for h in "${harnesses[@]}"; do
  while (($(jobs -rp | wc -l) >= JOBS)); do wait -n || true; done
  echo "   fuzz_$h (log: $BUILD/fuzz-logs/$h.log)"
  run_one "$h" &
done
wait
failed=()
summary=()
for h in "${harnesses[@]}"; do
  log=$BUILD/fuzz-logs/$h.log
  status=$(cat "$BUILD/fuzz-logs/$h.status" 2>/dev/null || echo 1)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  cov=$(grep -Eo 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -n 1)
  line="fuzz_$h: ${execs:-?} execs in ${SECONDS_PER_HARNESS} s, ${cov:-no coverage line}, corpus $(ls "$corpus/$h" | wc -l)"
  if ((status != 0)); then
    line+=" -> FAILED (exit $status; reproducer: $(ls -t "$BUILD/fuzz-artifacts/$h" | head -n 1))"
    failed+=("$h")
    grep -E '^==[0-9]+==ERROR|^SUMMARY|runtime error|uncaught|deadly signal|timeout|out-of-memory' "$log" | head -n 5 || true
  fi
  summary+=("$line")
done
echo "== fuzzing summary"
printf '%s\n' "${summary[@]}"
if ((${#failed[@]})); then
  echo "FAILED: ${failed[*]}"
  exit 1
fi
