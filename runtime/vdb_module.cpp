// runtime/vdb_module.cpp — the OpenVDB plug-in, libfortu_vdb.so (vdb.hpp): a narrow-band
// FloatGrid of a field, its inactive regions flood-filled with the side's sign.
#include "runtime/vdb.hpp"
#include "runtime/volume_order.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>

namespace fortu {
namespace {

/// io::File's layout (a seekable archive with grid offsets, which io::File reads back) into
/// any stream: Archive's stream writer is protected, io::File's opens its own unchecked file.
class MemoryArchive : public openvdb::io::Archive {
public:
    void write_to(std::ostream& os, const openvdb::GridCPtrVec& grids) const {
        Archive::write(os, grids, /*seekable=*/true);
    }
};

std::string encode(const Field& field, double band_cells, std::string& bytes) {
    try {
        openvdb::initialize();
        const Grid& g = field.grid;
        const std::array<double, 3> origin = volume_origin(g), spacing = volume_spacing(g);
        const double band = band_cells * std::min({spacing[0], spacing[1], spacing[2]});
        auto grid = openvdb::FloatGrid::create(static_cast<float>(-band));
        openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
        m.preScale(openvdb::Vec3d(spacing[0], spacing[1], spacing[2]));
        m.postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
        grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
        grid->setName("value");
        grid->insertMeta("fortu_convention", openvdb::StringMetadata("positive inside, zero on the surface"));
        auto accessor = grid->getAccessor();
        for_each_volume_row(field, [&](const double* row, int j, int k) {
            for (int i = 0; i < g.cols(); ++i)
                if (std::fabs(row[i]) <= band) accessor.setValue(openvdb::Coord(i, j, k), static_cast<float>(row[i]));
        });
        openvdb::tools::signedFloodFillWithValues(grid->tree(), static_cast<float>(band), static_cast<float>(-band));
        grid->pruneGrid();
        std::ostringstream out(std::ios::binary);
        MemoryArchive().write_to(out, {grid});
        if (!out) return "OpenVDB could not encode the grid";
        bytes = std::move(out).str();
        return "";
    } catch (const std::exception& e) {
        return e.what();
    }
}

const VdbModule kModule{kVdbModuleVersion, encode};

}  // namespace
}  // namespace fortu

extern "C" void* fortu_vdb_module() { return const_cast<fortu::VdbModule*>(&fortu::kModule); }
