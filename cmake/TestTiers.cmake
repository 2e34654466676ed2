# The test tiers: gives every test listed in tests/test_costs.txt its ctest labels, its TIMEOUT and
# its COST, from the seconds measured for it. Read by ctest, not by cmake: tests/tiers/ adds this
# file to TEST_INCLUDE_FILES of the last test directory, so that every test, the ones Catch
# discovers after each build included, is defined when it runs; a change to the table needs no
# reconfigure. Names the table holds that this build does not define (MPI or Python off) are
# ignored here; scripts/test_tiers.py check (a ctest) fails on a test without a line.
#
# Input: RUBCONT_TEST_COSTS, the table's path. Each line: seconds, tier, the test's full name:
#   quick   the tier run on every change (`ctest -L quick`, ./build.sh quick)
#   full    the rest of the suite (./build.sh test runs quick and full)
#   slow    the longest of full: labelled both "full" and "slow"
# TIMEOUT = 3 × seconds (rounded up) + 30 s: the seconds were measured on a shared 2-core machine
# under `ctest --parallel 2`, and a loaded day has been seen to run 2.2× slower (README.md).

if(NOT EXISTS "${RUBCONT_TEST_COSTS}")
  message(WARNING "${RUBCONT_TEST_COSTS} is missing: no test has a tier, a timeout or a cost")
  return()
endif()
# The lines as a list: a bracket in a name (intervals such as "[0.5, 2)", "[analysis.tori]")
# would join list elements, so brackets are stood in for while the text is split.
file(READ "${RUBCONT_TEST_COSTS}" rubcont_tier_text)
string(REPLACE "[" "<rubcont-open>" rubcont_tier_text "${rubcont_tier_text}")
string(REPLACE "]" "<rubcont-close>" rubcont_tier_text "${rubcont_tier_text}")
string(REPLACE ";" "<rubcont-semicolon>" rubcont_tier_text "${rubcont_tier_text}")
string(REPLACE "\n" ";" rubcont_tier_lines "${rubcont_tier_text}")
foreach(rubcont_tier_line IN LISTS rubcont_tier_lines)
  if(NOT rubcont_tier_line MATCHES "^[ \t]*[0-9]")
    continue()  # a comment or a blank line
  endif()
  string(REPLACE "<rubcont-open>" "[" rubcont_tier_line "${rubcont_tier_line}")
  string(REPLACE "<rubcont-close>" "]" rubcont_tier_line "${rubcont_tier_line}")
  string(REPLACE "<rubcont-semicolon>" ";" rubcont_tier_line "${rubcont_tier_line}")
  if(NOT rubcont_tier_line MATCHES
         "^[ \t]*([0-9]+)(\\.[0-9]*)?[ \t]+(quick|full|slow)[ \t]+([^ \t].*[^ \t]|[^ \t])[ \t]*$")
    message(WARNING "${RUBCONT_TEST_COSTS}: cannot read \"${rubcont_tier_line}\" "
                    "(wanted: seconds, quick|full|slow, the test's name)")
    continue()
  endif()
  # Kept before the next if(), which sets CMAKE_MATCH_<n> anew.
  set(rubcont_tier_whole "${CMAKE_MATCH_1}")
  set(rubcont_tier_fraction "${CMAKE_MATCH_2}")
  set(rubcont_tier "${CMAKE_MATCH_3}")
  set(rubcont_tier_test "${CMAKE_MATCH_4}")
  set(rubcont_tier_seconds "${rubcont_tier_whole}${rubcont_tier_fraction}")
  if(rubcont_tier_fraction MATCHES "[1-9]")
    math(EXPR rubcont_tier_whole "${rubcont_tier_whole} + 1")
  endif()
  math(EXPR rubcont_tier_timeout "3 * ${rubcont_tier_whole} + 30")
  if(rubcont_tier STREQUAL "slow")
    set(rubcont_tier_labels "full;slow")
  else()
    set(rubcont_tier_labels "${rubcont_tier}")
  endif()
  set_tests_properties("${rubcont_tier_test}" PROPERTIES LABELS "${rubcont_tier_labels}"
                       TIMEOUT ${rubcont_tier_timeout} COST ${rubcont_tier_seconds})
endforeach()
