// Transparent huge pages behind large arrays that are filled right after they are allocated (a
// scan's point arrays, the Ouster xyz lookup table): a 128-beam scan or table is 5-10 MB, and
// faulting it in 4 KB pages costs as much as filling it.
#pragma once

#include <cstddef>
#include <vector>

namespace dloam::drivers {

/// Asks the kernel to back the whole 2 MB pages within [data, data + bytes) with huge pages
/// (Linux: madvise MADV_HUGEPAGE; it may decline). Nothing elsewhere.
void advise_huge_pages(const void* data, std::size_t bytes);

/// The same for a vector's capacity.
template <class T>
void advise_huge_pages(const std::vector<T>& v) {
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace dloam::drivers
