#!/usr/bin/env bash
# The main job: builds impm and runs the seed's Problem 1 (traveling wave in a bar under a
# step load) with explicit MPM and GIMP, in plane stress (against E) and plane strain
# (against E/(1 - nu^2)). Prints the relative L2 errors against the exact solution and
# writes output/<deck>/{history.csv,summary.yaml,plot.png,particles.pvd}.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake/build.sh
BUILD="${IMPM_BUILD_DIR:-build}"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-2}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
for deck in apps/bar_explicit_mpm_plane_stress.yaml apps/bar_explicit_mpm_plane_strain.yaml \
            apps/bar_explicit_gimp_plane_stress.yaml apps/bar_explicit_gimp_plane_strain.yaml; do
  "$BUILD/apps/impm" "$deck"
done
