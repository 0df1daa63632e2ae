# Runs the impm driver on bad decks: each must exit with the status of its kind (2: the deck or
# its paths are wrong; 1: the run failed), with one line of impm's on stderr naming the key, and
# a bad deck must leave no output directory. Cases with NP 2 run under MPIEXEC: every rank must
# end (no hang) with the same status. Invoked by ctest (impm_bad_deck_cli).
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
file(READ "${SRC}/../apps/bar_explicit_mpm_plane_stress.yaml" good_bar)
file(READ "${SRC}/../apps/bar_explicit_mpm_plane_strain.yaml" good_bar_strain)
file(READ "${SRC}/../apps/colliding_disks_explicit_mpm.yaml" good_disks)
set(good "${good_bar}")

# Writes `deck` as WORK/<name>.yaml with its Output Directory set to `output`, runs impm on `np`
# ranks and checks the exit status and that impm wrote one line on stderr containing `key`
# (mpirun adds its own report of a failed rank: only impm's lines are counted).
function(run_and_check name deck output np expected_rc key)
  string(REGEX REPLACE "Output Directory: [^\n]*" "Output Directory: ${output}" deck "${deck}")
  file(WRITE "${WORK}/${name}.yaml" "${deck}")
  set(command "${IMPM}")
  if(NOT np EQUAL 1)
    separate_arguments(flags UNIX_COMMAND "${MPIEXEC_FLAGS}")
    set(command "${MPIEXEC}" ${flags} -np ${np} "${IMPM}")
  endif()
  # A hang (a rank left waiting in a barrier) fails here instead of at ctest's timeout.
  execute_process(COMMAND ${command} "${WORK}/${name}.yaml" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 120)
  if(NOT rc STREQUAL "${expected_rc}")
    message(FATAL_ERROR "${name}: impm exited '${rc}', expected ${expected_rc}: ${err}")
  endif()
  # (Semicolons would split the lists below.) A warning line (a Stability Factor above 1) is not
  # the error message: the one error line is counted without it.
  string(REPLACE ";" "," err "${err}")
  string(REGEX REPLACE "impm: warning:[^\n]*\n" "" err "${err}")
  string(REGEX MATCHALL "impm:[^\n]*\n" lines "${err}")
  list(LENGTH lines nlines)
  if(np EQUAL 1)
    string(REGEX MATCHALL "\n" all "${err}")
    list(LENGTH all nall)
  else()
    set(nall ${nlines})
  endif()
  if(NOT nlines EQUAL 1 OR NOT nall EQUAL 1)
    message(FATAL_ERROR "${name}: expected one line of impm's on stderr, got ${nlines}: ${err}")
  endif()
  string(FIND "${lines}" "${key}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "${name}: stderr does not name '${key}': ${err}")
  endif()
  message(STATUS "${name} (np ${np}, exit ${rc}): ok: ${lines}")
  set(error_line "${lines}" PARENT_SCOPE)  # for the checks that read numbers from the message
endfunction()

# A bad deck: exit 2, the key named, nothing written. NP (default 1) and OUTPUT (default
# WORK/out_<name>) may follow the four arguments.
function(expect_failure name search replace key)
  cmake_parse_arguments(C "" "NP;OUTPUT" "" ${ARGN})
  if(NOT C_NP)
    set(C_NP 1)
  endif()
  if(NOT C_OUTPUT)
    set(C_OUTPUT "${WORK}/out_${name}")
  endif()
  string(REPLACE "${search}" "${replace}" deck "${good}")
  if(deck STREQUAL good AND NOT search STREQUAL replace)  # (equal: only the output is bad)
    message(FATAL_ERROR "${name}: the test could not corrupt the deck ('${search}' not found)")
  endif()
  set(existed FALSE)
  if(EXISTS "${C_OUTPUT}")
    set(existed TRUE)  # a file where the directory should go
  endif()
  run_and_check(${name} "${deck}" "${C_OUTPUT}" ${C_NP} 2 "${key}")
  if((EXISTS "${C_OUTPUT}" AND NOT existed) OR IS_DIRECTORY "${C_OUTPUT}")
    message(FATAL_ERROR "${name}: output was written for a bad deck")
  endif()
  set(error_line "${error_line}" PARENT_SCOPE)
endfunction()

expect_failure(unknown_key "    Density: 7800.0" "    Density: 7800.0\n    Densty: 1.0" "Material/Densty")
expect_failure(wrong_type "Cells X: 30" "Cells X: thirty" "Grid/Cells X")
expect_failure(negative_modulus "Young Modulus: 200.0e9" "Young Modulus: -200.0e9" "Material/Young Modulus")
expect_failure(poisson "Poisson Ratio: 0.3" "Poisson Ratio: 0.5" "Material/Poisson Ratio")
expect_failure(zero_size "Cell Size Y: 0.5e-3" "Cell Size Y: 0.0" "Grid/Cell Size Y")
expect_failure(outside "X Max: 0.03" "X Max: 0.05" "Body/X Max")
expect_failure(unstable "Time Step: 1.0e-8" "Time Step: 1.0e-6" "Integrator/Time Step")
expect_failure(bad_choice "Update Scheme: USL" "Update Scheme: USX" "Integrator/Explicit/Update Scheme")
expect_failure(negative_damping "Update Scheme: USL" "Update Scheme: USL\n      Mass Damping: -1.0" "Integrator/Explicit/Mass Damping")
expect_failure(bad_preconditioner "  Output:" "  Implicit Solver:\n    Preconditioner: MAGIC\n  Output:" "Implicit Solver/Preconditioner")
expect_failure(bad_line_search "  Output:" "  Implicit Solver:\n    Line Search: Wolfe\n  Output:" "'Wolfe' for 'Implicit Solver/Line Search'")
expect_failure(contradicting_line_search "  Output:" "  Implicit Solver:\n    Line Search: Backtrack\n    NOX:\n      Line Search:\n        Method: Polynomial\n  Output:"
               "'Implicit Solver/NOX/Line Search/Method' = Polynomial contradicts 'Implicit Solver/Line Search' = Backtrack")
expect_failure(negative_tolerance "  Output:" "  Implicit Solver:\n    Displacement Tolerance: -1.0e-8\n  Output:" "Implicit Solver/Displacement Tolerance")
# Preconditioner: MUELU: MueLu's list is checked at deck time (a misspelt key, a value MueLu
# rejects); without MueLu in the Trilinos the preconditioner itself is refused.
if(MUELU)
  expect_failure(muelu_unknown_key "  Output:" "  Implicit Solver:\n    Preconditioner: MUELU\n    MueLu:\n      'smoother: tipe': RELAXATION\n  Output:" "Implicit Solver/MueLu/smoother: tipe")
  expect_failure(muelu_bad_value "  Output:" "  Implicit Solver:\n    Preconditioner: MUELU\n    MueLu:\n      'smoother: type': MAGIC\n  Output:" "Implicit Solver/MueLu")
else()
  expect_failure(muelu_unavailable "  Output:" "  Implicit Solver:\n    Preconditioner: MUELU\n  Output:" "Implicit Solver/Preconditioner")
endif()

# The Materials / Bodies form, on the colliding-disks deck.
set(good "${good_disks}")
expect_failure(unknown_material "      Material: elastic\n      Center X: 0.75" "      Material: rubber\n      Center X: 0.75" "Bodies/upper disk/Material")
expect_failure(disk_outside "Center X: 0.75" "Center X: 0.85" "Bodies/upper disk")
expect_failure(crossing_polygon "    upper disk:\n      Shape: Ellipse" "    upper disk:\n      Shape: Polygon\n      Vertices: 0.5, 0.5; 0.9, 0.9; 0.9, 0.5; 0.5, 0.9" "Bodies/upper disk/Vertices")
expect_failure(empty_polygon "    upper disk:\n      Shape: Ellipse" "    upper disk:\n      Shape: Polygon" "Bodies/upper disk/Vertices")
expect_failure(missing_file "    upper disk:\n      Shape: Ellipse" "    upper disk:\n      Shape: Particles File\n      File: ${WORK}/no_such.csv" "Bodies/upper disk/File")
expect_failure(mixed_forms "  Materials:" "  Body:\n    X Max: 0.5\n  Materials:" "'Body' is the single-body form")

# The output directory cannot be created: checked on rank 0 before any work, every
# rank ends with the same message (it hung at np 2).
file(WRITE "${WORK}/a_file" "not a directory\n")
set(good "${good_bar}")
expect_failure(output_in_proc "Name:" "Name:" "'Problem/Output Directory' = '/proc/impm_out' cannot be created"
               NP 2 OUTPUT /proc/impm_out)
expect_failure(output_under_file "Name:" "Name:" "'${WORK}/a_file' is not a directory" NP 2 OUTPUT "${WORK}/a_file/out")
expect_failure(output_is_file "Name:" "Name:" "exists and is not a directory" OUTPUT "${WORK}/a_file")
# A Node Force on a node no particle reaches (between the disks' corners) would act on nothing.
set(good "${good_disks}")
expect_failure(void_node_force "  Monitors:" "  Loads:\n    corner push:\n      Type: Node Force\n      X: 0.95\n      Y: 0.05\n      Force X: 1.0\n  Monitors:"
               "'Loads/corner push/Type' = Node Force at (0.95, 0.05): no particle reaches this grid node" NP 2)
# Prescribed motion (physics/GridConditions.hpp): a moving condition or a fixed node that no
# particle reaches, two conditions with different motions of one dof, a time table whose times do
# not increase, a value on a component the condition does not prescribe, and a value with Motion =
# Fixed. (The script reads stderr with ";" turned into ",".)
expect_failure(void_prescribed_motion "  Monitors:" "  Constraints:\n    corner grip:\n      Where: Node\n      X: 0.95\n      Y: 0.05\n      Motion: Velocity\n      Value X: 1.0\n  Monitors:"
               "'Constraints/corner grip/Motion' = Velocity: no particle reaches its grid nodes" NP 2)
expect_failure(void_fixed_node "  Monitors:" "  Constraints:\n    corner pin:\n      Where: Node\n      X: 0.95\n      Y: 0.05\n  Monitors:"
               "'Constraints/corner pin/Motion' = Fixed: no particle reaches its grid nodes at t = 0, so it would hold nothing")
set(good "${good_bar}")
set(pull "    rigid mode:\n      Where: Node\n      X: 0.0\n      Y: 0.0\n      Components: y\n    pull:\n      Where: Face\n      Face: x+\n      Components: x\n      Motion: Velocity\n      Value X: 0.1\n")
expect_failure(conflicting_motions "    rigid mode:\n      Where: Node\n      X: 0.0\n      Y: 0.0\n      Components: y\n"
               "${pull}    hold:\n      Where: Node\n      X: 0.03\n      Y: 0.0\n      Components: x\n"
               "'Constraints/pull' and 'Constraints/hold' prescribe different motions of component x of the grid node at (0.03, 0)")
expect_failure(table_not_increasing "    rigid mode:\n      Where: Node\n      X: 0.0\n      Y: 0.0\n      Components: y\n"
               "${pull}      Time Function: Table\n      Table: 0, 0; 1e-6, 1; 5e-7, 1\n"
               "'Constraints/pull/Table' = '0, 0, 1e-6, 1, 5e-7, 1': the times must increase, but 5e-07 follows 1e-06")
expect_failure(value_not_prescribed "    rigid mode:\n      Where: Node\n      X: 0.0\n      Y: 0.0\n      Components: y\n"
               "${pull}      Value Y: 0.1\n" "'Constraints/pull/Value Y' = 0.1 but 'Components' = x does not prescribe y")
expect_failure(value_with_fixed "      Components: y\n" "      Components: y\n      Value Y: 0.5\n"
               "'Constraints/rigid mode/Value Y' = 0.5 but 'Motion' is Fixed")
set(good "${good_disks}")
# A Newmark scheme that is not unconditionally stable (2 beta >= gamma >= 1/2).
set(good "${good_bar}")
expect_failure(newmark_unstable "Type: Explicit" "Type: Implicit\n    Implicit:\n      Newmark Beta: 0.25\n      Newmark Gamma: 0.7"
               "'Integrator/Implicit/Newmark Beta' = 0.25 and 'Newmark Gamma' = 0.7")
set(good "${good_disks}")
# A rank grid that leaves a rank without cells (the bar has one cell across y), and
# requested rank counts that do not multiply to the number of ranks.
set(good "${good_bar}")
expect_failure(rank_without_cells "  Output:" "  Decomposition:\n    Ranks Y: 2\n  Output:" "'Grid/Cells Y' = 1" NP 2)
expect_failure(rank_grid_product "  Output:" "  Decomposition:\n    Ranks X: 3\n    Ranks Y: 1\n  Output:" "'Decomposition/Ranks X'" NP 2)
# A Particle Force or a monitor far from every body (the nearest particle is over all ranks).
set(good "${good_bar}")
expect_failure(far_particle_force "  Loads:" "  Loads:\n    far push:\n      Type: Particle Force\n      X: 99\n      Y: 99\n      Force X: 1.0"
               "'Loads/far push/Type' = Particle Force at (99, 99): the nearest particle, at (0.0299, 0.00045), is 139.986 m away" NP 2)
expect_failure(far_monitor "  Monitors:" "  Monitors:\n    far:\n      Quantity: Velocity X\n      X: 99\n      Y: 99"
               "'Monitors/far' at (99, 99): the nearest particle, at (0.0299, 0.00045), is 139.986 m away")
# Sizes beyond the indices, or beyond the memory (the machine's, or Problem/Memory Limit GB).
expect_failure(huge_grid "Cells X: 30" "Cells X: 2000000000" "'Grid/Cells X' x 'Grid/Cells Y' = 2000000000 x 1 makes 4e+09 grid nodes")
set(ppc "Particles Per Cell X: 5\n    Particles Per Cell Y: 5")
expect_failure(particle_count_overflow "${ppc}" "Particles Per Cell X: 50000\n    Particles Per Cell Y: 50000"
               "the bodies make an estimated 7.5e+10 particles ('Bodies/Body/Particles Per Cell X' x 'Particles Per Cell Y' = 50000 x 50000), more than the 2147483647")
# 30 x 1 cells of 8000 x 8000 particles: 1.92e9 particles, whose views alone take 216 bytes each
# in 2D (ParticleSet::bytesPerParticle), 414.72 GB: more than any test machine has. The estimate
# must count every particle, at least those bytes for each, and add the grid's share.
expect_failure(out_of_memory "${ppc}" "Particles Per Cell X: 8000\n    Particles Per Cell Y: 8000"
               "the run needs an estimated")
if(NOT error_line MATCHES "needs an estimated ([0-9.]+) GB \\(grid ([0-9.]+) GB: [^)]*particles ([0-9.]+) GB: ([0-9.e+]+) particles")
  message(FATAL_ERROR "out_of_memory: the estimate's parts are not in the message: ${error_line}")
endif()
set(total_gb ${CMAKE_MATCH_1})
set(grid_gb ${CMAKE_MATCH_2})
set(particle_gb ${CMAKE_MATCH_3})
set(particle_count ${CMAKE_MATCH_4})
math(EXPR expected_particles "30 * 8000 * 8000")
math(EXPR view_bytes "30 * 8000 * 8000 * 216")
if(NOT particle_count EQUAL expected_particles OR particle_gb LESS 414.72 OR total_gb LESS particle_gb
   OR total_gb LESS grid_gb)
  message(FATAL_ERROR "out_of_memory: estimated ${total_gb} GB (grid ${grid_gb}, particles ${particle_gb} GB for "
                      "${particle_count} particles): want ${expected_particles} particles, at least ${view_bytes} bytes "
                      "for their views, and a total of at least its parts")
endif()
string(REPLACE "  Grid:" "    Memory Limit GB: 1\n  Grid:" good "${good_bar}")
expect_failure(memory_limit "${ppc}" "Particles Per Cell X: 500\n    Particles Per Cell Y: 500"
               "'Bodies/Body/Particles Per Cell X' x 'Particles Per Cell Y' = 500 x 500), more than 'Problem/Memory Limit GB' = 1" NP 2)

# 3D decks: a 2D-only option or shape, a bad dimension, a z key on a 2D grid.
file(READ "${SRC}/../apps/bar3d_explicit_mpm.yaml" good_bar3d)
file(READ "${SRC}/../apps/bar3d_implicit_gimp.yaml" good_bar3d_implicit_gimp)
set(good "${good_bar3d}")
expect_failure(plane_condition_3d "    Dimension: 3" "    Dimension: 3\n    Plane Condition: Plane Stress"
               "'Grid/Plane Condition' is a 2D idealisation")
expect_failure(dimension_4 "    Dimension: 3" "    Dimension: 4" "'Grid/Dimension' must be 2 or 3")
expect_failure(ellipse_3d "      Shape: Rectangle" "      Shape: Ellipse" "'Bodies/bar/Shape' = Ellipse is a 2D shape")
expect_failure(box_outside_3d "      Z Max: 0.5e-3" "      Z Max: 1.0e-3" "Bodies/bar/Z Max")
set(good "${good_bar3d_implicit_gimp}")
expect_failure(seed_gimp_stiffness_3d "    Implicit:" "    Implicit:\n      GIMP Stiffness: Integrated"
               "'Integrator/Implicit/GIMP Stiffness' = Integrated")
set(good "${good_bar}")
expect_failure(z_face_2d "      Face: x-" "      Face: z-" "'Constraints/fixed end/Face' = z- needs 'Grid/Dimension' = 3")
# Quadratic B-splines on the seed bar's single cell through the depth (a stencil spans 3 nodes).
expect_failure(bspline_one_cell "    Shape Function: MPM" "    Shape Function: B-Spline Quadratic"
               "'Method/Shape Function' = B-Spline Quadratic needs at least 2 cells per direction")
# Cubic B-splines likewise (a stencil spans 4 nodes: at least 3 cells per direction).
expect_failure(cubic_bspline_one_cell "    Shape Function: MPM" "    Shape Function: B-Spline Cubic"
               "'Method/Shape Function' = B-Spline Cubic needs at least 3 cells per direction")
expect_failure(z_key_2d "Cells Y: 1" "Cells Y: 1\n    Cells Z: 4" "'Grid/Cells Z' is a 3D key")
expect_failure(z_force_2d "      Force X: 1.0" "      Force X: 1.0\n      Force Z: 1.0" "'Loads/end force/Force Z'")

# An inverted particle (neo-Hookean disks at 2.8 times the stable step): exit 1, the message
# names the first inverted particle by global id and body, summary.yaml says diverged; at np 2
# every rank gives the same particle.
file(READ "${SRC}/../apps/colliding_disks_explicit_cpgimp_neohookean.yaml" disks)
string(REPLACE "Time Step: 1.0e-3" "Time Step: 0.06" disks "${disks}")
string(REPLACE "Number of Steps: 1500" "Number of Steps: 100" disks "${disks}")
string(REPLACE "      FLIP Fraction: 1.0" "      FLIP Fraction: 1.0\n      Stability Factor: 10" disks "${disks}")
string(REPLACE "Plot: true" "Plot: false" disks "${disks}")
foreach(np 1 2)
  set(output "${WORK}/out_inverted_np${np}")
  run_and_check(inverted_np${np} "${disks}" "${output}" ${np} 1 "of body 'lower disk'")
  if(NOT error_line MATCHES "particle ([0-9]+) of body 'lower disk'")
    message(FATAL_ERROR "inverted_np${np}: the message names no particle by id: ${error_line}")
  endif()
  set(inverted_id_np${np} ${CMAKE_MATCH_1})
  if(np EQUAL 2 AND NOT inverted_id_np2 EQUAL inverted_id_np1)
    message(FATAL_ERROR "inverted: np 2 names particle ${inverted_id_np2}, np 1 particle ${inverted_id_np1}")
  endif()
  file(READ "${output}/summary.yaml" summary)
  foreach(expected "Status: diverged" "is inverted: det F = -" "particle ${inverted_id_np${np}} of body ")
    string(FIND "${summary}" "${expected}" found)
    if(found EQUAL -1)
      message(FATAL_ERROR "inverted_np${np}: summary.yaml lacks '${expected}': ${summary}")
    endif()
  endforeach()
  # The last good state (the last history row's) is written beside the first step's VTU, and
  # none of its particles is inverted (every det F in it is positive).
  if(NOT EXISTS "${output}/particles_00001_r0.vtu")
    message(FATAL_ERROR "inverted_np${np}: no VTU of the last good state (particles_00001_r0.vtu)")
  endif()
  file(READ "${output}/particles_00001_r0.vtu" good_vtu)
  string(REGEX MATCH "Name=\"det_F\"[^>]*>[^<]*<" det_f "${good_vtu}")
  if(det_f STREQUAL "" OR det_f MATCHES "[ \n\t]-")
    message(FATAL_ERROR "inverted_np${np}: the last good state's det_F is missing or has a negative value")
  endif()
endforeach()

# A neo-Hookean material in plane stress, and with the FE reference; a Ramp load without its
# duration: rejected, naming the key.
set(good "${good_bar}")
expect_failure(neo_hookean_plane_stress "Model: Linear Elastic" "Model: Neo-Hookean"
               "'Materials/Material/Model' = Neo-Hookean is plane strain or 3D")
expect_failure(ramp_without_duration "Time Function: Step" "Time Function: Ramp" "Ramp Time' must be positive")
expect_failure(plastic_key_on_elastic "    Density: 7800.0" "    Density: 7800.0\n    Yield Stress: 1.0e6"
               "'Materials/Material/Yield Stress' is a J2 Plasticity parameter")
file(READ "${SRC}/../apps/bar_implicit_fe_q9_plane_strain.yaml" good)
expect_failure(neo_hookean_fe "Model: Linear Elastic" "Model: Neo-Hookean"
               "Model' = Neo-Hookean needs moving particles")
file(READ "${SRC}/../apps/column_implicit_cpgimp_neohookean.yaml" good)
expect_failure(j2_without_yield "Model: Neo-Hookean" "Model: J2 Plasticity" "'Materials/soil/Yield Stress' must be positive")
expect_failure(j2_negative_hardening "Model: Neo-Hookean" "Model: J2 Plasticity\n      Yield Stress: 1.0e5\n      Hardening Modulus: -1.0"
               "'Materials/soil/Hardening Modulus' must not be negative")
# Drucker-Prager: the friction angle in (0, 90), the dilatancy angle in [0, phi], the cohesion
# not negative, softening that the return can follow, a cone that exists.
set(dp "Model: Drucker-Prager\n      Cohesion: 1.0e4\n      Friction Angle: 30.0\n      Dilatancy Angle: 10.0")
expect_failure(dp_friction_angle_90 "Model: Neo-Hookean" "Model: Drucker-Prager\n      Friction Angle: 90.0"
               "'Materials/soil/Friction Angle' must lie in (0, 90) degrees, got 90")
expect_failure(dp_without_friction_angle "Model: Neo-Hookean" "Model: Drucker-Prager\n      Cohesion: 1.0e4"
               "'Materials/soil/Friction Angle' must lie in (0, 90) degrees, got 0")
expect_failure(dp_dilatancy_above_friction "Model: Neo-Hookean" "Model: Drucker-Prager\n      Friction Angle: 30.0\n      Dilatancy Angle: 35.0"
               "'Materials/soil/Dilatancy Angle' must lie in [0, Friction Angle = 30] degrees, got 35")
expect_failure(dp_negative_cohesion "Model: Neo-Hookean" "Model: Drucker-Prager\n      Friction Angle: 30.0\n      Cohesion: -1.0"
               "'Materials/soil/Cohesion' must not be negative")
expect_failure(dp_steep_softening "Model: Neo-Hookean" "${dp}\n      Cohesion Modulus: -1.0e12"
               "'Materials/soil/Cohesion Modulus' softens faster than the returns allow")
expect_failure(dp_unknown_cone "Model: Neo-Hookean" "${dp}\n      Cone: Middle"
               "Cone")
expect_failure(dp_key_on_j2 "Model: Neo-Hookean" "Model: J2 Plasticity\n      Yield Stress: 1.0e5\n      Cone: Outer"
               "'Materials/soil/Cone' is a Drucker-Prager parameter")
# Mohr-Coulomb: the shared checks, a tension cutoff between 0 and the apex c cot(phi), and no
# Drucker-Prager key.
set(mc "Model: Mohr-Coulomb\n      Cohesion: 1.0e4\n      Friction Angle: 30.0\n      Dilatancy Angle: 10.0")
expect_failure(mc_friction_angle_90 "Model: Neo-Hookean" "Model: Mohr-Coulomb\n      Cohesion: 1.0e4\n      Friction Angle: 90.0"
               "'Materials/soil/Friction Angle' must lie in [0, 90) degrees, got 90")
expect_failure(mc_dilatancy_above_friction "Model: Neo-Hookean" "Model: Mohr-Coulomb\n      Friction Angle: 30.0\n      Dilatancy Angle: 40.0"
               "'Materials/soil/Dilatancy Angle' must lie in [0, Friction Angle = 30] degrees, got 40")
expect_failure(mc_negative_cohesion "Model: Neo-Hookean" "Model: Mohr-Coulomb\n      Friction Angle: 30.0\n      Cohesion: -5.0"
               "'Materials/soil/Cohesion' must not be negative, got -5")
expect_failure(mc_steep_softening "Model: Neo-Hookean" "${mc}\n      Cohesion Modulus: -1.0e12"
               "'Materials/soil/Cohesion Modulus' softens faster than the returns allow")
expect_failure(mc_cutoff_above_apex "Model: Neo-Hookean" "${mc}\n      Tension Cutoff: 1.0e5"
               "'Materials/soil/Tension Cutoff' must lie in (0, Cohesion cot(Friction Angle) = ")
expect_failure(mc_negative_cutoff "Model: Neo-Hookean" "${mc}\n      Tension Cutoff: -1.0"
               "'Materials/soil/Tension Cutoff' must lie in (0, Cohesion cot(Friction Angle) = ")
expect_failure(mc_cone_key "Model: Neo-Hookean" "${mc}\n      Cone: Outer"
               "'Materials/soil/Cone' is a Drucker-Prager parameter")
expect_failure(mc_cutoff_on_dp "Model: Neo-Hookean" "${dp}\n      Tension Cutoff: 1.0e3"
               "'Materials/soil/Tension Cutoff' is a Mohr-Coulomb parameter")
# F-bar: plane strain or 3D, material points, Jacobian-free Newton.
file(READ "${SRC}/../apps/bar_explicit_mpm_plane_stress.yaml" good)
expect_failure(fbar_plane_stress "    Shape Function: MPM" "    Shape Function: MPM\n    Volumetric Locking: F-bar"
               "'Method/Volumetric Locking' = F-bar is for plane strain and 3D")
file(READ "${SRC}/../apps/bar_implicit_fe_q9_plane_strain.yaml" good)
expect_failure(fbar_fe_reference "    Shape Function: FE Q9" "    Shape Function: FE Q9\n    Volumetric Locking: F-bar"
               "'Method/Volumetric Locking' = F-bar is for material points")
file(READ "${SRC}/../apps/footing_displacement_implicit_gimp_j2.yaml" good)
expect_failure(fbar_assembled_jacobian "    Jacobian: Jacobian-Free" "    Jacobian: Assembled"
               "'Method/Volumetric Locking' = F-bar needs 'Implicit Solver/Jacobian' = Jacobian-Free")
expect_failure(unknown_locking_control "    Volumetric Locking: F-bar" "    Volumetric Locking: B-bar" "Volumetric Locking")
# Geostatic initial stress: K0 > 0, a surface above the body, gravity along -y, not Neo-Hookean.
file(READ "${SRC}/../apps/column_collapse_explicit_gimp_dp.yaml" good)
expect_failure(geostatic_negative_k0 "      Particles Per Cell Y: 2" "      Particles Per Cell Y: 2\n      Initial Stress: Geostatic\n      K0: -0.5\n      Surface Y: 0.12"
               "'Bodies/column/K0' must be positive")
expect_failure(geostatic_low_surface "      Particles Per Cell Y: 2" "      Particles Per Cell Y: 2\n      Initial Stress: Geostatic\n      K0: 0.5\n      Surface Y: 0.05"
               "'Bodies/column/Surface Y' = 0.05 lies below the body's highest particle")
expect_failure(k0_without_geostatic "      Particles Per Cell Y: 2" "      Particles Per Cell Y: 2\n      K0: 0.5"
               "'Bodies/column/K0' belongs to 'Initial Stress' = Geostatic")
string(REPLACE "      Particles Per Cell Y: 2" "      Particles Per Cell Y: 2\n      Initial Stress: Geostatic\n      K0: 0.5\n      Surface Y: 0.12"
       good "${good}")
expect_failure(geostatic_sideways_gravity "      Acceleration Y: -9.81" "      Acceleration Y: -9.81\n      Acceleration X: 1.0"
               "'Bodies/column/Initial Stress' = Geostatic takes gravity along -y")
expect_failure(geostatic_without_gravity "      Acceleration Y: -9.81" "      Acceleration Y: 0.0"
               "'Bodies/column/Initial Stress' = Geostatic needs gravity")
file(READ "${SRC}/../apps/column_implicit_cpgimp_neohookean.yaml" good)
expect_failure(geostatic_neo_hookean "      Particles Per Cell Y: 2" "      Particles Per Cell Y: 2\n      Initial Stress: Geostatic\n      K0: 0.5\n      Surface Y: 1.0"
               "'Bodies/column/Initial Stress' = Geostatic needs a material whose stress can start non-zero")
expect_failure(negative_minimum_step "    Type: Implicit" "    Type: Implicit\n    Implicit:\n      Adaptive Time Step: true\n      Minimum Time Step: -1.0"
               "'Integrator/Implicit/Minimum Time Step' must not be negative")
# The manufactured solution: its field, load and initial state belong together.
file(READ "${SRC}/../apps/mms_explicit_cpgimp_neohookean.yaml" good)
expect_failure(mms_linear_material "Model: Neo-Hookean" "Model: Linear Elastic"
               "'Bodies/block' must be made of a material with Model = Neo-Hookean")
expect_failure(mms_not_square "      Y Max: 1.0" "      Y Max: 0.5" "needs a square (3D: cube) body: 'Bodies/block' is 1 long in x and 0.5 in y")
expect_failure(mms_large_amplitude "Amplitude: 0.025" "Amplitude: 0.1" "'Exact Solution/Amplitude' must be positive and below")
expect_failure(mms_without_forcing "      Type: Manufactured Body Force" "      Type: Body Force"
               "needs a load of 'Type' = Manufactured Body Force")
expect_failure(mms_at_rest "    Type: Manufactured Solution\n" "    Type: None\n"
               "'Initial Conditions/Type' must be Manufactured Solution")
expect_failure(mms_forcing_alone "    Type: Axis-Aligned Manufactured Solution" "    Type: None"
               "'Initial Conditions/Type' = Manufactured Solution needs 'Exact Solution/Type' = Axis-Aligned")
set(good "${good_bar}")
# A diverging explicit run (dt 3.75 times the stable step, allowed by Stability Factor 5): exit
# 1 with a message that says so (not "particles left the grid"), summary.yaml Status: diverged,
# history.csv up to the last good step. At np 2 as well: every rank stops.
foreach(np 1 2)
  set(good "${good_bar_strain}")
  string(REPLACE "Time Step: 1.0e-8" "Time Step: 2.0e-7" deck "${good}")
  string(REPLACE "Number of Steps: 10000" "Number of Steps: 100" deck "${deck}")
  string(REPLACE "      Consistent Projection Iterations: 1" "      Consistent Projection Iterations: 1\n      Stability Factor: 5" deck "${deck}")
  string(REPLACE "History Interval: 10" "History Interval: 1" deck "${deck}")
  string(REPLACE "Plot: true" "Plot: false" deck "${deck}")
  set(output "${WORK}/out_diverged_np${np}")
  run_and_check(diverged_np${np} "${deck}" "${output}" ${np} 1 "the run diverged at step")
  # The step N the message names: its time is N dt, summary.yaml records N - 1 good steps and the
  # failed step N, history.csv holds steps 0 to N - 1, and np 2 stops at the same step as np 1.
  if(NOT error_line MATCHES "the run diverged at step ([0-9]+) \\(t = ([0-9.e+-]+) s\\)")
    message(FATAL_ERROR "diverged_np${np}: no step and time in the message: ${error_line}")
  endif()
  set(failed_step ${CMAKE_MATCH_1})
  set(failed_time ${CMAKE_MATCH_2})
  math(EXPR good_steps "${failed_step} - 1")
  math(EXPR expected_rows "${failed_step} + 1")
  math(EXPR time_in_ns "${failed_step} * 200")
  if(failed_step LESS 2 OR NOT failed_step LESS 100 OR NOT failed_time EQUAL "${time_in_ns}e-9")
    message(FATAL_ERROR "diverged_np${np}: step ${failed_step} at t = ${failed_time} s: want 1 < N < 100 and t = N x 2e-7 s")
  endif()
  set(diverged_step_np${np} ${failed_step})
  if(np EQUAL 2 AND NOT diverged_step_np2 EQUAL diverged_step_np1)
    message(FATAL_ERROR "diverged: np 2 stopped at step ${diverged_step_np2}, np 1 at ${diverged_step_np1}")
  endif()
  file(READ "${output}/summary.yaml" summary)
  foreach(expected "Status: diverged" "Steps: ${good_steps}\n" "Step: ${failed_step}\n")
    string(FIND "${summary}" "${expected}" found)
    if(found EQUAL -1)
      message(FATAL_ERROR "diverged_np${np}: summary.yaml lacks '${expected}': ${summary}")
    endif()
  endforeach()
  file(STRINGS "${output}/history.csv" rows)
  list(LENGTH rows nrows)
  if(NOT nrows EQUAL expected_rows)  # the header and steps 0 to N - 1
    message(FATAL_ERROR "diverged_np${np}: history.csv has ${nrows} lines, expected ${expected_rows} (header, steps 0 to ${good_steps})")
  endif()
endforeach()
# Output intervals: History Interval 0 and a negative VTK Interval have no meaning.
set(good "${good_bar}")
expect_failure(history_interval_zero "History Interval: 10" "History Interval: 0"
               "'Output/History Interval' must be at least 1")
expect_failure(vtk_interval_negative "VTK Interval: 1000" "VTK Interval: -3"
               "'Output/VTK Interval' must be 0 (first and last step only) or positive, got -3")
# The failure contract (doc/user-guide.md, "Exit status"): a run that stops early for any reason exits 1
# with one message, writes summary.yaml with Status and Failure, history.csv to the last good
# row, and the last good particles as VTU. `expect_stopped` checks them.
function(expect_stopped name deck np status key last_good_step rows)
  set(output "${WORK}/out_${name}")
  run_and_check(${name} "${deck}" "${output}" ${np} 1 "${key}")
  file(READ "${output}/summary.yaml" summary)
  foreach(expected "Status: ${status}" "Last Good Step: ${last_good_step}" "Reason: ")
    string(FIND "${summary}" "${expected}" found)
    if(found EQUAL -1)
      message(FATAL_ERROR "${name}: summary.yaml lacks '${expected}': ${summary}")
    endif()
  endforeach()
  string(REGEX MATCH "Last Good State: '?([a-z_0-9]+)_r" stem "${summary}")
  set(stem "${CMAKE_MATCH_1}")
  if(stem STREQUAL "" OR NOT EXISTS "${output}/${stem}_r0.vtu")
    message(FATAL_ERROR "${name}: no VTU of the last good state ('${stem}_r0.vtu'): ${summary}")
  endif()
  file(READ "${output}/particles.pvd" pvd)
  string(FIND "${pvd}" "${stem}_r0.vtu" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "${name}: particles.pvd does not list the last good state ${stem}")
  endif()
  file(STRINGS "${output}/history.csv" lines)
  list(LENGTH lines nlines)
  if(NOT nlines EQUAL ${rows})
    message(FATAL_ERROR "${name}: history.csv has ${nlines} lines, expected ${rows}")
  endif()
endfunction()
# Particles that leave the grid: the upper disk alone at 2 m/s towards x+ (no collision). Its
# rightmost particles sit at x = 0.9375 (2 per 0.05 m cell: sub-box centres 0.0125 + 0.025 k,
# inside r = 0.2 about 0.75), so their centres pass the grid's edge x = 1 at step 32
# (0.9375 + 32 x 0.002 = 1.0015). History every 10 steps: the last good row is step 30.
string(REPLACE "      Velocity X: -0.1\n      Velocity Y: -0.1" "      Velocity X: 2.0\n      Velocity Y: 0.0" deck "${good_disks}")
string(REPLACE "Number of Steps: 3500" "Number of Steps: 100" deck "${deck}")
string(REPLACE "Plot: true" "Plot: false" deck "${deck}")
foreach(np 1 2)
  expect_stopped(left_grid_np${np} "${deck}" ${np} "left the grid" "left the grid" 30 5)
endforeach()
# Newton that does not converge (one Newton iteration allowed on the neo-Hookean column, no step
# halving): the first step fails; the last good state is the initial one.
file(READ "${SRC}/../apps/column_implicit_cpgimp_neohookean.yaml" deck)
string(REPLACE "    Number of Steps: 24" "    Number of Steps: 24\n    Implicit:\n      Maximum Step Halvings: 0" deck "${deck}")
string(REPLACE "  Constraints:" "  Implicit Solver:\n    Maximum Newton Iterations: 1\n  Constraints:" deck "${deck}")
string(REPLACE "Plot: true" "Plot: false" deck "${deck}")
expect_stopped(newton_failed "${deck}" 1 "newton failed" "Newton did not converge" 0 2)
# Particle Placement (issue 9): an unknown value, and Gauss pairs with an odd count per cell.
set(good "${good_bar}")
expect_failure(bad_particle_placement "Particles Per Cell Y: 5" "Particles Per Cell Y: 5\n    Particle Placement: Gaus"
               "'Body/Particle Placement'")
expect_failure(gauss_odd_particles "Particles Per Cell Y: 5" "Particles Per Cell Y: 5\n    Particle Placement: Gauss"
               "'Bodies/Body/Particle Placement' = Gauss puts Gauss-Legendre pairs in sub-cells: 'Bodies/Body/Particles Per Cell X' must be even, got 5")
# Integrator/Explicit/Transfer: an unknown transfer; APIC or XPIC with the projection correction;
# APIC with a FLIP Fraction; an XPIC order outside [1, 40]; XPIC with multi-field contact; the
# explicit key with the implicit integrator; implicit APIC with the consistent mass or the FE reference. Bodies: an angular velocity about x in 2D.
set(good "${good_bar}")
expect_failure(unknown_transfer "FLIP Fraction: 1.0" "FLIP Fraction: 1.0\n      Transfer: PIC-FLIP" "Integrator/Explicit/Transfer")
expect_failure(xpic_with_projection "FLIP Fraction: 1.0" "FLIP Fraction: 1.0\n      Transfer: XPIC"
               "'Integrator/Explicit/Consistent Projection Iterations' = 0 (the projection correction and XPIC both filter v_p)")
expect_failure(apic_with_projection "FLIP Fraction: 1.0" "FLIP Fraction: 1.0\n      Transfer: APIC"
               "'Integrator/Explicit/Consistent Projection Iterations' = 0")
set(good "${good_disks}")
expect_failure(apic_with_flip_fraction "FLIP Fraction: 1.0" "FLIP Fraction: 0.5\n      Transfer: APIC"
               "'Integrator/Explicit/FLIP Fraction' at 1")
expect_failure(xpic_order_zero "FLIP Fraction: 1.0" "FLIP Fraction: 1.0\n      Transfer: XPIC\n      XPIC Order: 0"
               "'Integrator/Explicit/XPIC Order' must lie in [1, 40], got 0")
expect_failure(xpic_order_too_high "FLIP Fraction: 1.0" "FLIP Fraction: 1.0\n      Transfer: XPIC\n      XPIC Order: 41"
               "'Integrator/Explicit/XPIC Order' must lie in [1, 40], got 41")
file(READ "${SRC}/../apps/colliding_disks_contact_explicit_gimp.yaml" good)
expect_failure(xpic_with_contact "FLIP Fraction: 1.0" "FLIP Fraction: 1.0\n      Transfer: XPIC"
               "XPIC extrapolates one velocity field")
set(good "${good_disks}")
expect_failure(angular_velocity_x_2d "      Velocity Y: 0.1\n" "      Velocity Y: 0.1\n      Angular Velocity X: 1.0\n"
               "'Bodies/lower disk/Angular Velocity X' = 1 needs 'Grid/Dimension' = 3")
file(READ "${SRC}/../apps/bar_implicit_mpm_plane_stress.yaml" good)
expect_failure(tpic_implicit "    Implicit:" "    Explicit:\n      Transfer: TPIC\n    Implicit:"
               "'Integrator/Explicit/Transfer' = TPIC is the explicit integrator's transfer")
expect_failure(apic_implicit_consistent_mass "    Implicit:" "    Implicit:\n      Transfer: APIC\n      Mass Matrix: Consistent"
               "'Integrator/Implicit/Transfer' = APIC needs 'Integrator/Implicit/Mass Matrix' = Lumped")
file(READ "${SRC}/../apps/bar_implicit_fe_q9_plane_strain.yaml" good)
expect_failure(apic_fe_reference "    Implicit:\n      Mass Matrix" "    Implicit:\n      Transfer: APIC\n      Mass Matrix"
               "'Integrator/Implicit/Transfer' = APIC moves the particles")
