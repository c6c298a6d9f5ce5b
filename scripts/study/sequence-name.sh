# shellcheck shell=bash
# Sourced by the study scripts that render the street sequences, so that each finds the others'
# renders in a shared WORK folder: one name for one set of bolo simulate options.
#
#   study_sequence WORK TRAJECTORY SIZE FPS TAU SUPERSAMPLE LAG SUBSTEPS SEED   (prints the path)
#   study_render_options LAG SUBSTEPS   (sets the array study_render: simulate's lag options)
#   study_index_sequences INDEX   (prints "TRAJECTORY SEED SEQUENCE" once per sequence of a study index)
#
# The present renders (LAG exposure-readout, the simulator's sub-steps) keep the short name;
# another pixel lag or sub-step count is in the name.

study_sequence() {
  local tag=""
  [ "$7" = exposure-readout ] || tag="$tag-$7"
  [ -z "$8" ] || tag="$tag-k$8"
  echo "$1/seq-$2-$3-$4hz-tau$5-ss$6$tag-s$9"
}

study_render_options() {
  study_render=(--lag "$1")
  [ -z "$2" ] || study_render+=(--substeps "$2")
}

# A study index holds a line per run (`TRAJ SEED METHOD ... RUN`); bolo's runs are SEQUENCE-vo-MODE.
study_index_sequences() {
  awk '$6 ~ /-vo-/ { seq = $6; sub(/-vo-[^/]*$/, "", seq); if (!(seq in seen)) { seen[seq] = 1; print $1, $2, seq } }' "$1"
}
