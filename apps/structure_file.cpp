#include "apps/structure_file.h"

#include <array>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "apps/atomic_file.h"
#include "apps/hdf5_file.h"
#include "models/flexible.h"

namespace rubcont {
namespace {

constexpr std::array<const char*, 4> kNames = {"mass", "damping", "stiffness", "gyroscopic"};
// The largest dense model read: four 4000 × 4000 matrices are 512 MB; a larger FE model is reduced
// before it comes in (its rub structure keeps the contacts and a few modes in any case).
constexpr long kMaxCoordinates = 4000;

bool IsHdf5(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  return ext == ".h5" || ext == ".hdf5";
}

Matrix& Named(StructuralMatrices& m, std::size_t i) {
  return i == 0 ? m.mass : i == 1 ? m.damping : i == 2 ? m.stiffness : m.gyroscopic;
}
const Matrix& Named(const StructuralMatrices& m, std::size_t i) {
  return Named(const_cast<StructuralMatrices&>(m), i);
}

// One MatrixMarket file as a dense matrix. Eigen's loadMarket (unsupported/SparseExtra) is not
// used: it reports a bad line on std::cerr and goes on, and reads a symmetric file's one
// triangle as the whole matrix.
Matrix ReadMarket(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::invalid_argument(fmt::format("{}: cannot be read: no such file", file.string()));
  auto fail = [&](int line, const std::string& rule) {
    throw std::invalid_argument(fmt::format("{}:{}: {}", file.string(), line, rule));
  };
  std::string line;
  int number = 1;
  std::getline(in, line);
  std::istringstream header(line);
  std::string banner, object, format, field, symmetry;
  header >> banner >> object >> format >> field >> symmetry;
  for (std::string* word : {&object, &format, &field, &symmetry})
    for (char& c : *word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (banner != "%%MatrixMarket" || object != "matrix" ||
      (format != "coordinate" && format != "array") || (field != "real" && field != "integer") ||
      (symmetry != "general" && symmetry != "symmetric")) {
    fail(1, fmt::format("header \"{}\": must be \"%%MatrixMarket matrix coordinate|array "
                        "real|integer general|symmetric\"", line));
  }
  const bool symmetric = symmetry == "symmetric";
  long rows = -1, cols = -1, entries = -1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '%') continue;
    std::istringstream sizes(line);
    sizes >> rows >> cols;
    if (format == "coordinate") sizes >> entries;
    if (!sizes || rows < 1 || cols < 1 || (format == "coordinate" && entries < 0))
      fail(number, fmt::format("size line \"{}\": must be \"rows cols{}\", positive", line,
                               format == "coordinate" ? " entries" : ""));
    if (rows > kMaxCoordinates || cols > kMaxCoordinates)
      fail(number, fmt::format("{} × {}: at most {} coordinates are read (dense matrices); reduce "
                               "the model first", rows, cols, kMaxCoordinates));
    break;
  }
  if (rows < 0) fail(number, "no size line");
  Matrix out = Matrix::Zero(rows, cols);
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> given =
      Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(rows, cols, false);
  long read = 0;
  const long expected = format == "coordinate" ? entries
                        : symmetric           ? rows * (rows + 1) / 2
                                              : rows * cols;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '%') continue;
    if (read == expected) fail(number, fmt::format("more than the {} entries the size line gives", expected));
    std::istringstream entry(line);
    long i = 0, j = 0;
    double value = 0.0;
    if (format == "coordinate") {
      entry >> i >> j >> value;
      if (!entry) fail(number, fmt::format("entry \"{}\": must be \"row col value\"", line));
      if (i < 1 || i > rows || j < 1 || j > cols)
        fail(number, fmt::format("entry ({}, {}): outside the {} × {} matrix (indices from 1)", i, j,
                                 rows, cols));
      if (symmetric && j > i)
        fail(number, fmt::format("entry ({}, {}): a symmetric file lists the lower triangle (row ≥ col)",
                                 i, j));
    } else {
      entry >> value;
      if (!entry) fail(number, fmt::format("entry \"{}\": must be a number", line));
      // Column by column; a symmetric array lists each column's lower part (rows j … n).
      long k = read;
      j = 1;
      for (long length = rows; k >= length; length = symmetric ? rows - j + 1 : rows) {
        k -= length;
        ++j;
      }
      i = (symmetric ? j : 1) + k;
    }
    if (given(i - 1, j - 1)) fail(number, fmt::format("entry ({}, {}): given twice", i, j));
    given(i - 1, j - 1) = true;
    out(i - 1, j - 1) = value;
    if (symmetric) out(j - 1, i - 1) = value;
    ++read;
  }
  if (read != expected)
    fail(number, fmt::format("{} entries: the size line gives {}", read, expected));
  return out;
}

void WriteMarket(const std::filesystem::path& file, const Matrix& x) {
  std::string text = "%%MatrixMarket matrix coordinate real general\n"
                     "% written by rubcont scene matrices (apps/structure_file.h)\n";
  long entries = 0;
  for (Index j = 0; j < x.cols(); ++j)
    for (Index i = 0; i < x.rows(); ++i) entries += x(i, j) != 0.0 ? 1 : 0;
  text += fmt::format("{} {} {}\n", x.rows(), x.cols(), entries);
  for (Index j = 0; j < x.cols(); ++j)
    for (Index i = 0; i < x.rows(); ++i)
      if (x(i, j) != 0.0) text += fmt::format("{} {} {:.17g}\n", i + 1, j + 1, x(i, j));
  WriteFileAtomically(file, text);
}

}  // namespace

StructuralMatrices ReadStructuralMatrices(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    throw std::invalid_argument(fmt::format("{}: cannot be read: no such file or directory",
                                            path.string()));
  }
  StructuralMatrices out;
  if (IsHdf5(path)) {
    try {
      const ResultReader reader(path);
      for (std::size_t i = 0; i < kNames.size(); ++i) {
        const std::string dataset = std::string("/") + kNames[i];
        if (!reader.Exists(dataset))
          throw std::invalid_argument(fmt::format("{}: has no dataset {} (n × n doubles)",
                                                  path.string(), dataset));
        Named(out, i) = reader.ReadMatrix(dataset);
        if (Named(out, i).rows() > kMaxCoordinates || Named(out, i).cols() > kMaxCoordinates)
          throw std::invalid_argument(fmt::format(
              "{}: {} is {} × {}: at most {} coordinates are read (dense matrices); reduce the "
              "model first", path.string(), dataset, Named(out, i).rows(), Named(out, i).cols(),
              kMaxCoordinates));
      }
    } catch (const std::runtime_error& e) {
      throw std::invalid_argument(e.what());
    }
  } else if (std::filesystem::is_directory(path, error)) {
    for (std::size_t i = 0; i < kNames.size(); ++i)
      Named(out, i) = ReadMarket(path / (std::string(kNames[i]) + ".mtx"));
  } else {
    throw std::invalid_argument(fmt::format(
        "{}: must be an HDF5 file (.h5, .hdf5) or a directory of MatrixMarket files (mass.mtx, "
        "damping.mtx, stiffness.mtx, gyroscopic.mtx)", path.string()));
  }
  try {
    CheckStructuralMatrices(out);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("{}: {}", path.string(), e.what()));
  }
  return out;
}

void WriteStructuralMatrices(const std::filesystem::path& path, const StructuralMatrices& matrices) {
  if (IsHdf5(path)) {
    PrepareToWrite(path);
    ResultWriter writer(path);
    for (std::size_t i = 0; i < kNames.size(); ++i)
      writer.WriteMatrix(std::string("/") + kNames[i], Named(matrices, i));
    writer.Commit();
    return;
  }
  std::filesystem::create_directories(path);
  for (std::size_t i = 0; i < kNames.size(); ++i)
    WriteMarket(path / (std::string(kNames[i]) + ".mtx"), Named(matrices, i));
}

}  // namespace rubcont
