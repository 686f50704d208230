#include "spectral/colour_model.h"

#include <fmt/format.h>

#include <charconv>
#include <optional>
#include <nlohmann/json.hpp>

#include "base/atomic_file.h"
#include "spectral/colorimetry.h"
#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "base/json_reader.h"
#include "spectral/linear_model.h"

namespace svr {

std::string toString(ModelKind kind) {
  switch (kind) {
    case ModelKind::kRgb: return "rgb";
    case ModelKind::kSpectral: return "spectral";
    case ModelKind::kFactor: return "factor";
    case ModelKind::kLinear: return "linear";
  }
  return "?";
}

std::string toString(LightMatrixKind kind) {
  return kind == LightMatrixKind::kFull ? "full" : "projected";
}

namespace {

// "full" or "projected"; nothing for any other text.
std::optional<LightMatrixKind> lightMatrixFromString(const std::string& text) {
  for (auto kind : {LightMatrixKind::kFull, LightMatrixKind::kProjected})
    if (toString(kind) == text) return kind;
  return std::nullopt;
}

}  // namespace

std::string ModelName::str() const {
  const std::string base = kind == ModelKind::kRgb ? "rgb" : fmt::format("{}:{}", toString(kind), k);
  return light_matrix == defaultLightMatrix(kind) ? base : base + "/" + toString(light_matrix);
}

namespace {

ModelName parseBaseName(const std::string& text) {
  if (text == "rgb") return {ModelKind::kRgb, 3};
  const auto colon = text.find(':');
  const std::string head = text.substr(0, colon);
  ModelKind kind;
  int lo = 1, hi = 16;
  if (head == "factor") {
    kind = ModelKind::kFactor, lo = 3;
  } else if (head == "spectral") {
    kind = ModelKind::kSpectral, lo = 3, hi = 100000;
  } else if (head == "linear") {
    kind = ModelKind::kLinear, lo = 3;
  } else {
    throw Error(fmt::format("unknown colour model '{}'; expected rgb, factor:k, spectral:n or "
                            "linear:k", text));
  }
  if (colon == std::string::npos)
    throw Error(fmt::format("colour model '{}' needs a channel count, e.g. '{}:6'", text, head));
  int k = 0;
  const std::string num = text.substr(colon + 1);
  const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), k);
  if (ec != std::errc() || end != num.data() + num.size() || num.empty())
    throw Error(fmt::format("colour model '{}': channel count '{}' is not an integer", text, num));
  if (k < lo || k > hi)
    throw Error(fmt::format("colour model '{}': channel count {} is outside {}..{}", text, k, lo,
                            hi));
  return {kind, k};
}

}  // namespace

ModelName parseModelName(const std::string& text) {
  const auto slash = text.find('/');
  ModelName name = parseBaseName(text.substr(0, slash));
  if (slash == std::string::npos) return name;
  const std::string matrix = text.substr(slash + 1);
  const std::optional<LightMatrixKind> kind = lightMatrixFromString(matrix);
  if (!kind)
    throw Error(fmt::format("colour model '{}': light matrix '{}' is not 'full' or 'projected'",
                            text, matrix));
  if (*kind == LightMatrixKind::kFull &&
      (name.kind == ModelKind::kRgb || name.kind == ModelKind::kLinear))
    throw Error(fmt::format("colour model '{}': {} has no spectral basis for full-spectrum "
                            "light matrices; it relights projected only",
                            text, toString(name.kind)));
  name.light_matrix = *kind;
  return name;
}

namespace {

Eigen::MatrixXd matrixFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array()) throw Error(fmt::format("{}: expected an array of rows", where));
  if (j.empty()) return {};
  const size_t cols = j[0].size();
  Eigen::MatrixXd m(j.size(), cols);
  for (size_t r = 0; r < j.size(); ++r) {
    if (!j[r].is_array() || j[r].size() != cols)
      throw Error(fmt::format("{}: row {} does not have {} numbers", where, r, cols));
    for (size_t c = 0; c < cols; ++c) {
      if (!j[r][c].is_number())
        throw Error(fmt::format("{}: row {} column {} is not a number", where, r, c));
      m(r, c) = j[r][c].get<double>();
    }
  }
  if (!m.allFinite()) throw Error(fmt::format("{}: contains a non-finite number", where));
  return m;
}

}  // namespace

nlohmann::json matrixToJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    std::vector<double> row(m.cols());
    for (Eigen::Index c = 0; c < m.cols(); ++c) row[c] = m(r, c);
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json ColourModel::jsonHead() const {
  return {{"model", name()},
          {"variant", variant()},
          {"light_matrix", toString(light_matrix_)},
          {"grid", {{"start_nm", grid_.start_nm}, {"step_nm", grid_.step_nm}, {"count", grid_.count}}},
          {"to_xyz", matrixToJson(to_xyz_)}};
}

std::unique_ptr<ColourModel> modelFromJson(const nlohmann::json& j, const std::string& source) {
  try {
    ModelName name = parseModelName(j.at("model").get<std::string>());
    // Files written before full-spectrum light matrices existed name no light matrix and were
    // all projected.
    const std::string matrix = j.value("light_matrix", "projected");
    const std::optional<LightMatrixKind> kind = lightMatrixFromString(matrix);
    if (!kind)
      throw Error(fmt::format("{}: light_matrix '{}' is not 'full' or 'projected'", source, matrix));
    name.light_matrix = *kind;
    const auto& g = j.at("grid");
    WavelengthGrid grid{g.at("start_nm").get<double>(), g.at("step_nm").get<double>(),
                        g.at("count").get<int>()};
    validate(grid);
    const std::string variant = j.value("variant", "");
    const Eigen::MatrixXd to_xyz = matrixFromJson(j.at("to_xyz"), source + ": to_xyz");
    const Eigen::MatrixXd basis = matrixFromJson(j.at("basis"), source + ": basis");
    const int k = name.kind == ModelKind::kLinear ? static_cast<int>(basis.cols()) : name.k;
    if (to_xyz.rows() != 3 || to_xyz.cols() != k)
      throw Error(fmt::format("{}: to_xyz is {}×{}, expected 3×{}", source, to_xyz.rows(),
                              to_xyz.cols(), k));
    if (name.kind == ModelKind::kLinear) {
      if (basis.rows() != grid.count || basis.cols() != name.k)
        throw Error(fmt::format("{}: basis is {}×{}, expected {}×{}", source, basis.rows(),
                                basis.cols(), grid.count, name.k));
      return std::make_unique<LinearModel>(grid, basis, to_xyz);
    }
    const Eigen::MatrixXd projection = matrixFromJson(j.at("projection"), source + ": projection");
    if (projection.rows() != name.k || projection.cols() != grid.count)
      throw Error(fmt::format("{}: projection is {}×{}, expected {}×{}", source, projection.rows(),
                              projection.cols(), name.k, grid.count));
    XyzMatrix spectrum_to_xyz;
    if (name.light_matrix == LightMatrixKind::kFull) {
      spectrum_to_xyz = matrixFromJson(j.at("spectrum_to_xyz"), source + ": spectrum_to_xyz");
      if (spectrum_to_xyz.rows() != 3 || spectrum_to_xyz.cols() != grid.count)
        throw Error(fmt::format("{}: spectrum_to_xyz is {}×{}, expected 3×{}", source,
                                spectrum_to_xyz.rows(), spectrum_to_xyz.cols(), grid.count));
    }
    return std::make_unique<ComponentwiseModel>(name.kind, variant, grid, projection, to_xyz,
                                                basis, name.light_matrix, spectrum_to_xyz);
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: not a colour model: {}", source, e.what()));
  }
}

void saveModel(const ColourModel& model, const std::string& path) {
  writeTextAtomically(path, model.toJson().dump(1) + "\n");
}

std::unique_ptr<ColourModel> loadModel(const std::string& path) {
  return modelFromJson(JsonReader::parseFile(path), path);
}

}  // namespace svr
