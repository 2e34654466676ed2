// A structure's matrices in a file, for [flexible.matrices] (apps/scene.h MatrixSettings): an FE
// model's M, C, K, G brought in, or a scene's written out (`rubcont scene matrices`). Two formats,
// chosen by the path:
//   FILE.h5 (or .hdf5)  HDF5 datasets /mass, /damping, /stiffness, /gyroscopic, each n × n doubles;
//   DIR                 a directory with MatrixMarket files mass.mtx, damping.mtx, stiffness.mtx,
//                       gyroscopic.mtx ("matrix coordinate real general|symmetric", or "matrix
//                       array real general"; 1-based indices; a symmetric file lists one triangle).
// The matrices are one plane's, real and symmetric, of M ü + (C − jωG) u̇ + K u = f on complex
// coordinates u = x + j y (models/beam.h): written out in real coordinates (x, y) the gyroscopic
// term is ω [[0, G], [−G, 0]] (ẋ, ẏ) — the usual skew-symmetric G of a 4-dof-per-node FE model,
// whose x–z block is G here (docs/levels/l4_flexible.md, "Your own matrices").
#pragma once

#include <filesystem>

#include "models/beam.h"

namespace rubcont {

// Reads and checks the four matrices (CheckStructuralMatrices, models/flexible.h). Throws
// std::invalid_argument naming the file (and line), the matrix and the rule: a missing or
// unreadable file, a malformed MatrixMarket line, an entry out of range or given twice, a shape
// unlike the mass's, more than 4000 coordinates (the matrices are dense), an asymmetric or
// indefinite matrix.
StructuralMatrices ReadStructuralMatrices(const std::filesystem::path& path);

// Writes them in the format the path says (an .h5 file atomically; a directory's .mtx files with
// 17 significant digits, which read back to the same doubles). Throws std::runtime_error on an
// I/O error.
void WriteStructuralMatrices(const std::filesystem::path& path, const StructuralMatrices& matrices);

}  // namespace rubcont
