# Warnings on everywhere; -Wno-array-bounds for GCC 12's false positives in Eigen fixed-size code
# (-Wno-stringop-overflow is GCC's only: clang, used for the fuzz harnesses, does not know it).
add_library(dloam_warnings INTERFACE)
target_compile_options(dloam_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wno-array-bounds
                                                $<$<CXX_COMPILER_ID:GNU>:-Wno-stringop-overflow>)
if(DLOAM_WERROR)
  target_compile_options(dloam_warnings INTERFACE -Werror)
endif()
if(DLOAM_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
  # GCC 12 with the sanitizers reports std::regex's and std::function's own members as "maybe
  # uninitialized" (its libstdc++ headers, not dloam's code).
  target_compile_options(dloam_warnings INTERFACE $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
endif()
