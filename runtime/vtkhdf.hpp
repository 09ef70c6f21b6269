// runtime/vtkhdf.hpp — a volume as a VTKHDF ImageData file (.hdf, .vtkhdf), which ParaView
// 5.10+ and VTK's vtkHDFReader open: group /VTKHDF with the attributes Version, Type,
// WholeExtent, Origin, Spacing and Direction, and the dataset /VTKHDF/PointData/value
// (Float64, slices × rows × columns; with --mimages n1..n5 beside it), written brick by brick.
//
// Why parallel HDF5: under mpirun every rank writes its bricks' hyperslabs into the one
// file (MPI-IO; the file's structure is made and closed collectively), so no rank gathers
// the volume. The dataset is contiguous and allocated when created, so writing values
// changes no metadata: a killed run leaves a valid file with holes, which --resume fills.
#pragma once

#include "runtime/brick_output.hpp"

#include <memory>
#include <string>

namespace fortu {

/// The .hdf/.vtkhdf brick writer. Throws OutputError (also when fortu was built without
/// HDF5, or with a serial HDF5 and spec.collective).
std::unique_ptr<BrickOutput> open_vtkhdf_bricks(const BrickOutputSpec& spec);

}  // namespace fortu
