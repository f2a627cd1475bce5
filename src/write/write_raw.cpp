// Headerless raw writer: the samples alone, x fastest, in the header's type and byte order,
// optionally gzip-compressed (.raw.gz). Dims, type, byte order, spacing and value scale are
// not stored: a reader needs them given (vdbmesh --raw-dims, --raw-type, --raw-endian, --spacing).

#include "volume_writers.h"

namespace vdbmesh::detail {

WriteResult write_raw(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                      bool gzip) {
    check_volume_header(path, header);
    write_attached(path, "", gzip, header, slices);
    return {{path}, false};
}

}  // namespace vdbmesh::detail
