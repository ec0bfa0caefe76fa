# SPDX-License-Identifier: GPL-3.0-or-later
# `translucent pathtrace sphere|mesh` and `translucent integrate sphere|mesh` through the real binary
# (tests/cli/check.cmake: runs and writes a well-formed file, or fails with a message naming the
# problem). Included from CMakeLists.txt.
if(TARGET translucent_cli)
  set(T $<TARGET_FILE:translucent_cli>)
  set(OUT ${CMAKE_CURRENT_BINARY_DIR})
  set(CHECK ${PROJECT_SOURCE_DIR}/tests/cli/check.cmake)
  function(render_test name)
    cmake_parse_arguments(C "FAIL" "FILE;MATCH" "ARGS" ${ARGN})
    add_test(NAME cli.render_${name}
             COMMAND ${CMAKE_COMMAND} -DEXE=${T} "-DARGS=${C_ARGS}" -DEXPECT_FAIL=${C_FAIL}
                     -DFILE=${C_FILE} "-DMATCH=${C_MATCH}" -P ${CHECK})
    set_tests_properties(cli.render_${name} PROPERTIES LABELS cli)
  endfunction()
  set(SMALL --width 12 --height 12 --threads 2)
  render_test(sphere_json ARGS pathtrace sphere --material Skin1 --scale 2 ${SMALL} --photons 4000
              --passes 2 --exr ${OUT}/rs.exr --png ${OUT}/rs.png --json ${OUT}/rs.json
              FILE ${OUT}/rs.json MATCH "\"photons_per_channel\": 8192")
  render_test(sphere_png ARGS pathtrace sphere --sigma-a 0.1 --sigma-s 1 --g 0.5 --eta 1.4
              --light-dir 0,1,1 --quantity cone-radiance ${SMALL} --photons 3000
              --exr ${OUT}/rs2.exr --png ${OUT}/rs2.png --exposure 2 --gamma 2.2
              FILE ${OUT}/rs2.png MATCH "PNG")
  render_test(sphere_time_limit ARGS pathtrace sphere --material Marble ${SMALL} --photons 1e15
              --time-limit 0.3 --exr ${OUT}/rs3.exr --json ${OUT}/rs3.json
              FILE ${OUT}/rs3.json MATCH "\"partial\": true")
  # --device (issue 16): the GPU walk writes the same outputs and says what traced them; time
  # limits act between its batches; unknown devices are refused.
  render_test(sphere_device_gpu ARGS pathtrace sphere --material Skin1 --scale 2 ${SMALL}
              --photons 4000 --device gpu --exr ${OUT}/rsg.exr --json ${OUT}/rsg.json
              FILE ${OUT}/rsg.json MATCH "\"device\": \"gpu \\(")
  render_test(sphere_device_gpu_time_limit ARGS pathtrace sphere --material Marble ${SMALL}
              --photons 1e15 --device gpu --time-limit 0.5 --exr ${OUT}/rsg2.exr
              --json ${OUT}/rsg2.json FILE ${OUT}/rsg2.json MATCH "\"partial\": true")
  # The split by scattering order (issue 14 §4): EXR layers per order, fluxes per order.
  # (The layers themselves: tests/python/test_reference.py reads them with OpenImageIO.)
  render_test(sphere_split_orders ARGS pathtrace sphere --material Skin1 --scale 2 ${SMALL}
              --photons 4000 --split-orders --exr ${OUT}/rso.exr --json ${OUT}/rso.json
              FILE ${OUT}/rso.json MATCH "\"split_orders\": true")
  render_test(sphere_flux_by_order ARGS pathtrace sphere --material Skin1 --scale 2 ${SMALL}
              --photons 4000 --exr ${OUT}/rso2.exr --json ${OUT}/rso2.json
              FILE ${OUT}/rso2.json MATCH "\"exited_by_order\": {[^}]*\"multiple\"")
  render_test(mesh_split_orders ARGS pathtrace mesh --scene ${PROJECT_SOURCE_DIR}/data/scenes/cube.json
              --photons 2000 --split-orders --exr ${OUT}/rmso.exr --json ${OUT}/rmso.json
              FILE ${OUT}/rmso.json MATCH "\"split_orders\": true")
  render_test(sphere_device_bad FAIL ARGS pathtrace sphere ${SMALL} --device tpu
              --exr ${OUT}/x.exr MATCH "--device")
  render_test(mesh_device_gpu ARGS pathtrace mesh --scene ${PROJECT_SOURCE_DIR}/data/scenes/cube.json
              --photons 4000 --device gpu --exr ${OUT}/rmg.exr --json ${OUT}/rmg.json
              FILE ${OUT}/rmg.json MATCH "\"device\": \"gpu \\(")
  render_test(mesh_device_gpu_environment ARGS pathtrace mesh
              --scene ${PROJECT_SOURCE_DIR}/data/compare/bunny-marble-environment.json
              --photons 2000 --device gpu --exr ${OUT}/rmge.exr
              --json ${OUT}/rmge.json FILE ${OUT}/rmge.json MATCH "\"device\": \"gpu \\(")
  # 3D fields on the GPU (fields.glsl): the veined marble bunny, layers below the head's surface, a
  # deformed (bent) bunny.
  render_test(mesh_device_gpu_field ARGS pathtrace mesh
              --scene ${PROJECT_SOURCE_DIR}/data/scenes/bunny-marble-veins.json
              --photons 4000 --device gpu --exr ${OUT}/rmgf.exr --json ${OUT}/rmgf.json
              FILE ${OUT}/rmgf.json MATCH "\"device\": \"gpu \\(")
  render_test(mesh_device_gpu_surface_layers ARGS pathtrace mesh
              --scene ${PROJECT_SOURCE_DIR}/data/scenes/head-layered-skin.json
              --photons 2000 --device gpu --exr ${OUT}/rmgl.exr --json ${OUT}/rmgl.json
              FILE ${OUT}/rmgl.json MATCH "\"device\": \"gpu \\(")
  render_test(mesh_device_gpu_deformed_field ARGS pathtrace mesh
              --scene ${PROJECT_SOURCE_DIR}/data/scenes/bunny-bend.json
              --photons 2000 --device gpu --exr ${OUT}/rmgd.exr --json ${OUT}/rmgd.json
              FILE ${OUT}/rmgd.json MATCH "\"device\": \"gpu \\(")
  render_test(integrate_json ARGS integrate sphere --model dipole --material Ketchup ${SMALL}
              --samples 4 --sampling uniform --exr ${OUT}/ri.exr --json ${OUT}/ri.json
              FILE ${OUT}/ri.json MATCH "\"samples_per_pixel\": 4")
  # Directional models (issue 14 §1): the C++ directional dipole on the CPU, its .bssrdf twin on
  # the GPU with the light's direction (uniform sampling, said in the JSON).
  render_test(integrate_directional ARGS integrate sphere --model directional-dipole
              --material Skin1 --light-dir 1,0,1 ${SMALL} --samples 8 --exr ${OUT}/rid.exr
              --json ${OUT}/rid.json FILE ${OUT}/rid.json MATCH "\"device\": \"cpu\"")
  render_test(integrate_directional_bssrdf ARGS integrate sphere
              --model ${PROJECT_SOURCE_DIR}/data/bssrdf/directional-dipole.bssrdf
              --material Skin1 --light-dir 1,0,1 ${SMALL} --samples 64 --exr ${OUT}/ridb.exr
              --json ${OUT}/ridb.json FILE ${OUT}/ridb.json MATCH "\"sampling\": \"uniform\"")
  render_test(mesh_json ARGS pathtrace mesh --scene ${PROJECT_SOURCE_DIR}/data/scenes/cube.json
              --photons 2000 --threads 2 --quantity radiance --exr ${OUT}/rm.exr
              --json ${OUT}/rm.json FILE ${OUT}/rm.json MATCH "\"triangles\": 12")
  # --time: the deformed mesh at that time (mesh.deform; the JSON's scene records the time).
  render_test(mesh_time ARGS pathtrace mesh --scene ${PROJECT_SOURCE_DIR}/data/scenes/bunny-bend.json
              --time 0.5 --photons 2000 --threads 2 --exr ${OUT}/rm_time.exr
              --json ${OUT}/rm_time.json FILE ${OUT}/rm_time.json MATCH "\"time\": 0.5")
  # A convex mesh: no photon re-enters, so none scores into two pixels.
  render_test(mesh_convex_json ARGS pathtrace mesh --scene ${PROJECT_SOURCE_DIR}/data/scenes/cube.json
              --photons 2000 --threads 2 --exr ${OUT}/rm2.exr --json ${OUT}/rm2.json
              FILE ${OUT}/rm2.json MATCH "\"photons_in_several_pixels\": 0,")
  render_test(integrate_mesh_json ARGS integrate mesh
              --scene ${PROJECT_SOURCE_DIR}/data/scenes/cube.json --samples 20000 --threads 2
              --quantity radiance --exr ${OUT}/rim.exr --png ${OUT}/rim.png --json ${OUT}/rim.json
              FILE ${OUT}/rim.json MATCH "\"lit_samples\"")
  render_test(integrate_mesh_exr ARGS integrate mesh
              --scene ${PROJECT_SOURCE_DIR}/data/scenes/cube.json --samples 20000 --threads 2
              --jitter --exr ${OUT}/rim2.exr --json ${OUT}/rim2.json
              FILE ${OUT}/rim2.json MATCH "\"jitter\": true")
  render_test(integrate_mesh_passes FAIL ARGS integrate mesh
              --scene ${PROJECT_SOURCE_DIR}/data/scenes/cube.json --passes 2 --exr ${OUT}/x.exr
              MATCH "one pass")
  render_test(integrate_mesh_bad_convention FAIL ARGS integrate mesh
              --scene ${PROJECT_SOURCE_DIR}/data/scenes/cube.json --convention foo
              --exr ${OUT}/x.exr MATCH "--convention")
  render_test(sphere_nan FAIL ARGS pathtrace sphere --sigma-a nan --sigma-s 1 --exr ${OUT}/x.exr
              MATCH "sigma_a .red channel. is nan")
  render_test(sphere_bad_light FAIL ARGS pathtrace sphere --light-dir 0,0 --exr ${OUT}/x.exr
              MATCH "--light-dir")
  render_test(sphere_bad_radius FAIL ARGS pathtrace sphere --radius -2 --exr ${OUT}/x.exr
              MATCH "radius is -2")
  render_test(sphere_unwritable FAIL ARGS pathtrace sphere --exr ${OUT}/no_such_dir/x.exr
              MATCH "--exr")
  render_test(integrate_bad_model FAIL ARGS integrate sphere --model foo --exr ${OUT}/x.exr
              MATCH "valid models are")
  render_test(mesh_missing_scene FAIL ARGS pathtrace mesh --scene ${OUT}/no_scene.json
              --exr ${OUT}/x.exr MATCH "no_scene.json")
  file(WRITE ${OUT}/missing_mesh.json "{\"mesh\": {\"file\": \"nowhere.obj\"}, \"material\": "
       "{\"preset\": \"Marble\"}, \"lights\": [{\"type\": \"directional\", \"direction\": "
       "[0, 1, 0]}], \"camera\": {\"position\": [0, 0, 5]}}")
  render_test(mesh_missing_mesh FAIL ARGS pathtrace mesh --scene ${OUT}/missing_mesh.json
              --exr ${OUT}/x.exr MATCH "mesh.file: file 'nowhere.obj' not found")
  add_test(NAME cli.render_sigint
           COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/sigint_render.sh ${T} ${OUT})
  set_tests_properties(cli.render_sigint PROPERTIES LABELS cli TIMEOUT 120)
endif()
