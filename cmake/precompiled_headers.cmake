# Precompiled headers where nearly every translation unit of a target includes the same heavy
# headers: OpenVDB's in the OpenVDB stages, CLI11's and nlohmann/json's in the subcommands.
# A PCH only saves the parsing (OpenVDB ~3-4 s, CLI11 + json ~4-5 s of CPU per file, measured
# with GCC 12 at -O3), and costs every file of its target that would not have included those
# headers its loading and more code to generate (a file of vdbmesh_cli without OpenVDB went
# from 0.5 s to 6.4 s with OpenVDB in the PCH). Hence none for the tests (GoogleTest parses in
# under a second; OpenVDB is in less than half of their files) and no OpenVDB in vdbmesh_cli's.
# -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON switches them off (to check that each file includes
# what it uses: a precompiled header hides a missing #include).

# The OpenVDB stages: one PCH, built with vdbmesh_grid (the first stage with OpenVDB), reused
# by the later ones whose files mostly include OpenVDB (same flags: static libraries, -fPIC;
# GCC refuses a PCH built with other code-generation flags). The OpenVDB-free stages get none.
function(vdbmesh_precompile_openvdb target)
  if(target STREQUAL vdbmesh_grid)
    target_precompile_headers(${target} PRIVATE <openvdb/openvdb.h>)
  else()
    target_precompile_headers(${target} REUSE_FROM vdbmesh_grid)
  endif()
endfunction()

# The subcommands (vdbmesh_cli): CLI11 in 27 of their 31 files, nlohmann/json in 19.
function(vdbmesh_precompile_cli target)
  target_precompile_headers(${target} PRIVATE <CLI/CLI.hpp> <nlohmann/json.hpp>)
endfunction()

# The Python module (_vdbmesh): pybind11 in every file (~4 s of CPU each).
function(vdbmesh_precompile_python target)
  target_precompile_headers(${target} PRIVATE <pybind11/pybind11.h>)
endfunction()
