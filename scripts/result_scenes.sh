# Sourced by scripts/regenerate-results.sh and scripts/check_results.sh (from the repository root).
# The scenes of a kind (quick, sweep, orbits, loop), one per line.
scenes_of() { awk -v k="$1" '$1 == k { print $2 }' scripts/result_scenes.txt; }
# A committed loop's options: those of its own line in scripts/result_scenes.txt after the scene's
# name, else those of the `options loop` line.
loop_options_of() {
  awk -v s="$1" '$1 == "options" && $2 == "loop" { $1 = $2 = ""; common = $0 }
    $1 == "loop" && $2 == s && NF > 2 { $1 = $2 = ""; own = $0 }
    END { print (own != "" ? own : common) }' scripts/result_scenes.txt
}
