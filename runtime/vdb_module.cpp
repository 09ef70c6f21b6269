// runtime/vdb_module.cpp — the OpenVDB plug-in, libfortu_vdb.so (vdb.hpp): a narrow-band
// FloatGrid of a field, its inactive regions flood-filled with the side's sign. A whole field
// (encode) and a bricked run (begin/add/finish) build it the same way, voxel by voxel.
#include "runtime/vdb.hpp"
#include "runtime/volume_order.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
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

struct Builder {
    double band = 0;
    openvdb::FloatGrid::Ptr grid;
    openvdb::FloatGrid::Accessor accessor;

    explicit Builder(const Grid& g, double band_cells)
        : band(vdb_band_width(g, band_cells)), grid(openvdb::FloatGrid::create(static_cast<float>(-band))),
          accessor(grid->getAccessor()) {
        const std::array<double, 3> origin = volume_origin(g), spacing = volume_spacing(g);
        openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
        m.preScale(openvdb::Vec3d(spacing[0], spacing[1], spacing[2]));
        m.postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
        grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
        grid->setName("value");
        grid->insertMeta("fortu_convention", openvdb::StringMetadata("positive inside, zero on the surface"));
    }

    std::string finish(std::string& bytes) {
        accessor.clear();
        openvdb::tools::signedFloodFillWithValues(grid->tree(), static_cast<float>(band), static_cast<float>(-band));
        grid->pruneGrid();
        std::ostringstream out(std::ios::binary);
        MemoryArchive().write_to(out, {grid});
        if (!out) return "OpenVDB could not encode the grid";
        bytes = std::move(out).str();
        return "";
    }
};

void* begin(const Grid& grid, double band_cells) {
    try {
        openvdb::initialize();
        return new Builder(grid, band_cells);
    } catch (const std::exception&) {
        return nullptr;
    }
}

void add(void* builder, const std::int32_t* ijk, const float* values, std::size_t count) {
    auto& b = *static_cast<Builder*>(builder);
    for (std::size_t n = 0; n < count; ++n)
        b.accessor.setValue(openvdb::Coord(ijk[3 * n], ijk[3 * n + 1], ijk[3 * n + 2]), values[n]);
}

std::string finish(void* builder, std::string& bytes) {
    std::unique_ptr<Builder> b(static_cast<Builder*>(builder));
    try {
        return b->finish(bytes);
    } catch (const std::exception& e) {
        return e.what();
    }
}

void discard(void* builder) { delete static_cast<Builder*>(builder); }

std::size_t memory(void* builder) { return static_cast<Builder*>(builder)->grid->tree().memUsage(); }

std::string encode(const Field& field, double band_cells, std::string& bytes) {
    try {
        openvdb::initialize();
        const Grid& g = field.grid;
        Builder b(g, band_cells);
        for_each_volume_row(field, [&](const double* row, int j, int k) {
            for (int i = 0; i < g.cols(); ++i)
                if (std::fabs(row[i]) <= b.band) b.accessor.setValue(openvdb::Coord(i, j, k), static_cast<float>(row[i]));
        });
        return b.finish(bytes);
    } catch (const std::exception& e) {
        return e.what();
    }
}

const VdbModule kModule{kVdbModuleVersion, encode, begin, add, finish, discard, memory};

}  // namespace
}  // namespace fortu

extern "C" void* fortu_vdb_module() { return const_cast<fortu::VdbModule*>(&fortu::kModule); }
