#include "write_text_file.h"

#include <fstream>

#include "vdbmesh/atomic_file.h"
#include "vdbmesh/error.h"

namespace vdbmesh::cli {

void write_text_file(const std::string& path, const std::string& text) {
    AtomicFile file(path);
    {
        std::ofstream out(file.temp_path(), std::ios::binary);
        out << text;
        out.close();
        if (!out) throw Error(path + ": cannot write");
    }
    file.commit();
}

}  // namespace vdbmesh::cli
