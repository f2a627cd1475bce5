#include <string>
#include <vector>

#include "cli.h"

int main(int argc, char** argv) {
    return vdbmesh::cli::run(std::vector<std::string>(argv + 1, argv + argc));
}
