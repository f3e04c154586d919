// Memory policy of a dloam process (the `dloam` tool, dloam_node, the benchmarks): a recording is
// decoded into a few MB of fresh arrays per scan (a 128-beam scan holds 5-10 MB of points, a bag's
// messages as much again), freed a scan later. With glibc's defaults, blocks that large are mapped
// on allocation and unmapped on free, so every scan faults its arrays in again page by page, which
// on a virtual machine costs more than decoding them (docs/recordings.md). Kept in the heap
// instead, freed blocks are reused without a fault.
#pragma once

namespace dloam::run {

/// Serves blocks up to 64 MB from the heap and keeps up to 256 MB of freed memory there for reuse
/// (glibc mallopt; nothing elsewhere). Call once at the start of main(), before any thread starts;
/// a library embedded in another program (the Python module) leaves the host's policy alone.
void reuse_freed_memory();

}  // namespace dloam::run
