// interp/engine_table.cpp — the one table of engines. Adding an engine: its own files (a
// class implementing Engine, engine.hpp) and one row here; every command that names engines
// (run --engine, bench --engines, golden-engine, the REPL's :engine, the help texts) reads
// this table.
#include "interp/engine.hpp"

#include "interp/classic_engine.hpp"
#include "interp/fv_engine.hpp"
#include "interp/sign_render.hpp"
#include "interp/voxel_engine.hpp"

namespace fortu {
namespace {

const ClassicEngine kClassic;
const VoxelEngine kVoxel;
const VoxelEngine kVoxelFloat32({.precision = Precision::Float32});
const SignEngine kSign;
const FvEngine kFv;

/// In the order help texts and `fortu bench` list them.
const Engine* const kEngines[] = {&kClassic, &kVoxel, &kVoxelFloat32, &kSign, &kFv};

}  // namespace

std::span<const Engine* const> engine_table() { return kEngines; }

const Engine& default_engine() { return kVoxel; }

}  // namespace fortu
