# SPDX-License-Identifier: GPL-3.0-or-later
# Reference transport in scenes (included from CMakeLists.txt): the photon walk through closed
# bodies (transport.h), the lit sphere (sphere.h), BSSRDF integration on the sphere
# (sphere_integration.h), triangle meshes through Embree (mesh_tracer.h, mesh_scene.h), and the
# model reference: a BSSRDF model integrated over a mesh (model_reference.h).
find_package(glm REQUIRED)
find_package(embree 3 REQUIRED)

add_library(translucent_reference_scenes STATIC
  transport.cpp
  mc_image.cpp
  run_state.cpp  # partial files of sharded runs (issue 17)
  camera.cpp
  sphere.cpp
  sphere_integration.cpp
  mesh_tracer.cpp
  surface_transfer.cpp  # transport from surface entry discs (the transfer technique)
  camera_paths.cpp  # the mesh reference from the camera: backward paths with next-event estimation
  refracted_light.cpp  # its next-event estimation through a refractive boundary (eta != 1)
  majorant_grid.cpp  # heterogeneous media: delta tracking through a majorant grid
  model_reference.cpp)  # scene files: src/scene (mesh_scene.h maps the old names)
add_library(translucent::reference_scenes ALIAS translucent_reference_scenes)
target_link_libraries(translucent_reference_scenes
  PUBLIC translucent::reference translucent::bssrdf translucent::geometry translucent::lights
         translucent::material glm::glm
  PRIVATE embree TBB::tbb nlohmann_json::nlohmann_json fmt::fmt Threads::Threads)
translucent_project_target(translucent_reference_scenes)
# The model reference's inner loop over samples: `omp simd` (no OpenMP runtime), sqrt without
# errno (its arguments are squared distances, >= 0).
set_source_files_properties(model_reference.cpp PROPERTIES COMPILE_OPTIONS
  "$<$<CXX_COMPILER_ID:GNU,Clang>:-fno-math-errno;-fopenmp-simd>")
