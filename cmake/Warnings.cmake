# Warnings on everywhere; -Wno-array-bounds for GCC 12's false positives in Eigen fixed-size code.
add_library(dloam_warnings INTERFACE)
target_compile_options(dloam_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wno-array-bounds
                                                -Wno-stringop-overflow)
if(DLOAM_WERROR)
  target_compile_options(dloam_warnings INTERFACE -Werror)
endif()
if(DLOAM_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
