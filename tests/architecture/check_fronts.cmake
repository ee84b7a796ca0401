cmake_minimum_required(VERSION 3.18)
# The Python module binds the libraries and compiles no file of apps/; apps/ holds fronts that
# parse, call and print: no experiment driver, no scorer, no statistics helper of its own.
set(errors "")
file(GLOB python_files ${SOURCE_DIR}/python/CMakeLists.txt ${SOURCE_DIR}/python/*.cpp ${SOURCE_DIR}/python/*.hpp)
foreach(f IN LISTS python_files)
  file(READ ${f} text)
  if(text MATCHES "apps/[A-Za-z_]+\\.(cpp|hpp)|cli_common|cmd_[a-z_]+\\.cpp")
    string(APPEND errors "  ${f}: refers to apps/ (${CMAKE_MATCH_0}); bind the library instead\n")
  endif()
endforeach()
file(GLOB app_files ${SOURCE_DIR}/apps/*.cpp ${SOURCE_DIR}/apps/*.hpp)
# What only the libraries may do: run work units, write run directories, drive trackers and
# score them, compute order statistics.
set(forbidden
  "ScenarioRunner" "UnitSink" "write_unit\\(" "read_units\\(" "enumerate_units\\(" "update_run_info\\("
  "double (quantile|percentile|median)\\(" "std::nth_element" "walked \\+=")
foreach(f IN LISTS app_files)
  file(READ ${f} text)
  foreach(pattern IN LISTS forbidden)
    if(text MATCHES "${pattern}")
      string(APPEND errors "  ${f}: \"${CMAKE_MATCH_0}\" belongs in a library (scenarios/, bench/, eval/)\n")
    endif()
  endforeach()
endforeach()
if(errors)
  message(FATAL_ERROR "fronts that do a library's work:\n${errors}")
endif()
message(STATUS "python/ binds libraries only; apps/ holds fronts only")
