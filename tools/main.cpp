#include <string>
#include <vector>

#include "cli.h"
#include "vdbmesh/ranks.h"

int main(int argc, char** argv) {
    // MPI for the run when started by mpirun (in a build with VDBMESH_MPI); nothing otherwise.
    const vdbmesh::RanksSession ranks;
    return vdbmesh::cli::run(std::vector<std::string>(argv + 1, argv + argc));
}
