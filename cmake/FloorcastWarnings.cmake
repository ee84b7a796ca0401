# Warnings for floorcast's own targets only (never for third-party code).
function(floorcast_target_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANG_AND_ID:CXX,GNU,Clang>:-Wall -Wextra -Wpedantic>)
endfunction()
