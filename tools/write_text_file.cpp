#include "write_text_file.h"

#include "vdbmesh/checked_output.h"

namespace vdbmesh::cli {

void write_text_file(const std::string& path, const std::string& text) {
    CheckedOutput file(path);
    file.stream() << text;
    file.commit();
}

}  // namespace vdbmesh::cli
