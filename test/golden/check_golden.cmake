# Golden histories: short runs of the project's decks at one thread whose history.csv (17
# significant digits) and solver counters must stay identical bit for bit, and the stored
# `impm --print-defaults`. A refactoring that keeps answers keeps these files; a change that
# moves answers regenerates them on purpose (-DUPDATE=ON) and says why in its commit.
#   OMP_NUM_THREADS=1 cmake -DIMPM=build/apps/impm -DSRC=. -DWORK=/tmp/golden [-DUPDATE=ON] [-DONLY=name] -P test/golden/check_golden.cmake
# Each case: name, deck in apps/, number of steps, history interval, then pairs of
# "regex" "replacement" applied to the deck text (a scheme or shape function swapped in).
set(CASES
  "usl_mpm|bar_explicit_mpm_plane_strain.yaml|300|10"
  "usf_mpm|bar_explicit_mpm_plane_strain.yaml|300|10|Update Scheme: USL|Update Scheme: USF"
  "musl_mpm|bar_explicit_mpm_plane_strain.yaml|300|10|Update Scheme: USL|Update Scheme: MUSL"
  "usl_gimp|bar_explicit_gimp_plane_strain.yaml|300|10"
  "usf_gimp|bar_explicit_gimp_plane_strain.yaml|300|10|Update Scheme: USL|Update Scheme: USF"
  "musl_gimp|bar_explicit_gimp_plane_strain.yaml|300|10|Update Scheme: USL|Update Scheme: MUSL"
  "usl_bspline|bar_explicit_bspline_plane_stress.yaml|200|10"
  "two_bodies_gimp|bar_two_material_explicit_gimp.yaml|300|10"
  "disks_mpm|colliding_disks_explicit_mpm.yaml|200|10"
  "disks_cpgimp_neohookean|colliding_disks_explicit_cpgimp_neohookean.yaml|100|10"
  "cpdi_musl_neohookean|cantilever_explicit_cpdi_neohookean.yaml|200|10"
  "dam_gimp_gravity|dam_under_gravity_explicit_gimp.yaml|100|10"
  "rod_impact_3d_gimp|rod_impact_3d_explicit_gimp.yaml|20|2"
  "implicit_jfnk_mpm|beam_implicit_mpm_plane_strain.yaml|20|1"
  "implicit_jfnk_gimp|beam_implicit_gimp_plane_strain.yaml|20|1"
  "implicit_jfnk_bspline|beam_implicit_bspline_plane_strain.yaml|10|1"
  "implicit_assembled_fe_q9|bar_implicit_fe_q9_plane_strain.yaml|50|5"
  "implicit_assembled_fe_q4|beam_implicit_fe_q4_plane_strain.yaml|20|1"
  "implicit_assembled_j2_gimp|footing_implicit_gimp_j2.yaml|20|1"
  "implicit_cpdi_neohookean|cantilever_implicit_cpdi_neohookean.yaml|3|1"
  "implicit_cpgimp_column|column_implicit_cpgimp_neohookean.yaml|4|1"
  "implicit_bar3d_mpm|bar3d_implicit_mpm.yaml|10|1"
  "implicit_platens_j2_displacement|platens_implicit_mpm_j2.yaml|20|1"
  "wall_bar_gimp|bar_wall_impact_explicit_gimp.yaml|500|10"
  "wall_block_friction_gimp|block_sliding_friction_explicit_gimp.yaml|400|40"
  "contact_disks_gimp|colliding_disks_contact_explicit_gimp.yaml|1500|50"
  "contact_incline_usf_gimp|block_incline_contact_explicit_gimp.yaml|400|40|Update Scheme: USL|Update Scheme: USF"
  "contact_incline_musl_gimp|block_incline_contact_explicit_gimp.yaml|400|40|Update Scheme: USL|Update Scheme: MUSL"
  "contact_rigid_platen_gimp|platen_compression_rigid_explicit_gimp.yaml|300|20"
  "explicit_platens_gimp_velocity|platens_implicit_mpm_j2.yaml|400|40|Type: Implicit|Type: Explicit|Time Step: 0.5|Time Step: 2.0e-5|Shape Function: MPM|Shape Function: GIMP|Motion: Displacement|Motion: Velocity|Value Y: -0.01|Value Y: -1.0|Ramp Time: 10.0|Ramp Time: 2.0e-3"
)
# Lines of summary.yaml that count solver work (and the run's status).
set(COUNTERS "Status:|Newton Iterations|Krylov Iterations|Step Halvings|Stiffness Assemblies|Residual Norms Of Hardest Step|Residual Evaluations|Sub-Steps|Migrations:|Migrated Particles:")

set(GOLDEN ${SRC}/test/golden)
file(MAKE_DIRECTORY ${WORK})
set(failures "")

function(compare_or_update name produced stored)
  if(UPDATE)
    file(COPY_FILE ${produced} ${stored})
    message(STATUS "${name}: stored ${stored}")
    return()
  endif()
  if(NOT EXISTS ${stored})
    set(failures "${failures} ${name}(no ${stored})" PARENT_SCOPE)
    return()
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${produced} ${stored} RESULT_VARIABLE differ)
  if(differ)
    execute_process(COMMAND diff ${stored} ${produced} OUTPUT_VARIABLE d)
    string(SUBSTRING "${d}" 0 1500 d)
    message("${name}: ${produced} differs from ${stored}:\n${d}")
    set(failures "${failures} ${name}" PARENT_SCOPE)
  else()
    message(STATUS "${name}: identical")
  endif()
endfunction()

if(NOT ONLY OR ONLY STREQUAL "print_defaults")
  execute_process(COMMAND ${IMPM} --print-defaults OUTPUT_FILE ${WORK}/print-defaults.txt RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "impm --print-defaults exited with ${rc}")
  endif()
  compare_or_update(print_defaults ${WORK}/print-defaults.txt ${GOLDEN}/print-defaults.txt)
endif()

foreach(case IN LISTS CASES)
  string(REPLACE "|" ";" fields "${case}")
  list(POP_FRONT fields name deck steps interval)
  if(ONLY AND NOT ONLY STREQUAL name)
    continue()
  endif()
  file(READ ${SRC}/apps/${deck} text)
  string(REGEX REPLACE "Number of Steps: [0-9]+" "Number of Steps: ${steps}" text "${text}")
  string(REGEX REPLACE "( *)History Interval: [0-9]+" "\\1History Interval: ${interval}\n\\1History Digits: 17" text "${text}")
  string(REGEX REPLACE "Plot: true" "Plot: false" text "${text}")
  string(REGEX REPLACE "Checkpoint Interval: [0-9]+" "Checkpoint Interval: 0" text "${text}")
  while(fields)
    list(POP_FRONT fields from to)
    string(REGEX REPLACE "${from}" "${to}" text "${text}")
  endwhile()
  set(dir ${WORK}/${name})
  file(REMOVE_RECURSE ${dir})
  file(WRITE ${WORK}/${name}.yaml "${text}")
  execute_process(COMMAND ${IMPM} ${WORK}/${name}.yaml --output ${dir} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message("${name}: impm exited with ${rc}:\n${out}")
    set(failures "${failures} ${name}(exit ${rc})")
    continue()
  endif()
  file(STRINGS ${dir}/summary.yaml lines REGEX "${COUNTERS}")
  string(REPLACE ";" "\n" lines "${lines}")
  file(WRITE ${dir}/counters.txt "${lines}\n")
  compare_or_update(${name}_history ${dir}/history.csv ${GOLDEN}/${name}.history.csv)
  compare_or_update(${name}_counters ${dir}/counters.txt ${GOLDEN}/${name}.counters.txt)
endforeach()

if(failures)
  message(FATAL_ERROR "golden histories changed:${failures}")
endif()
