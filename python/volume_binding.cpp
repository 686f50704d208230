// svr.Volume.from_numpy: a 3-D numpy array as svr's Volume (x fastest, design.md §7). The array's
// axes are named by `axes`: "xyz" (a[x, y, z], as VTK, PyVista and nibabel index) or "zyx"
// (a[z, y, x], as TIFF stacks, scikit-image and pydicom slices do). A Fortran-ordered "xyz"
// array or a C-ordered "zyx" one is x-fastest already and is taken with one straight copy into
// the volume (svr's volumes own their voxels; copies of a scene share them); other layouts are
// transposed in that same copy.

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>

#include "python/bindings.h"
#include "renderers/volume/memory_budget.h"
#include "renderers/volume/volume.h"

namespace svr::python {
namespace {

// Native byte order only: a byte-swapped array ('>u2' on this machine) is named as such.
ScalarType scalarTypeOf(const py::array& a) {
  if (py::isinstance<py::array_t<std::uint8_t>>(a)) return ScalarType::kUint8;
  if (py::isinstance<py::array_t<std::uint16_t>>(a)) return ScalarType::kUint16;
  if (py::isinstance<py::array_t<std::int16_t>>(a)) return ScalarType::kInt16;
  if (py::isinstance<py::array_t<float>>(a)) return ScalarType::kFloat32;
  throw py::value_error(fmt::format(
      "Volume.from_numpy: {} is not one of uint8, uint16, int16, float32 in native byte order "
      "(convert with a.astype(np.float32))",
      py::repr(a.dtype()).cast<std::string>()));
}

// Index of the first non-finite value of a float32 array in array order, or -1.
py::ssize_t firstNonFinite(const py::array& a) {
  const auto* v = static_cast<const float*>(a.data());
  for (py::ssize_t i = 0; i < a.size(); ++i)
    if (!std::isfinite(v[i])) return i;  // contiguous: memory order is one of the two orders
  return -1;
}

// The array's voxels in svr's order (x fastest), from any C- or Fortran-contiguous layout.
std::vector<std::byte> voxelsXFastest(const py::array& a, const int axis_of[3], const Dims& d) {
  const std::size_t w = static_cast<std::size_t>(a.itemsize());
  const py::ssize_t sx = a.strides(axis_of[0]), sy = a.strides(axis_of[1]),
                    sz = a.strides(axis_of[2]);
  std::vector<std::byte> out(static_cast<std::size_t>(d[0]) * d[1] * d[2] * w);
  const auto* base = static_cast<const std::byte*>(a.data());
  std::byte* dest = out.data();
  if (sx == static_cast<py::ssize_t>(w) && sy == sx * d[0] && sz == sy * d[1]) {
    std::memcpy(dest, base, out.size());  // x fastest already
    return out;
  }
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y) {
      const std::byte* row = base + z * sz + y * sy;
      for (int x = 0; x < d[0]; ++x, dest += w) std::memcpy(dest, row + x * sx, w);
    }
  return out;
}

PyVolume fromNumpy(const py::array& a, std::tuple<double, double, double> spacing,
         const std::string& axes) {
  if (a.ndim() != 3)
    throw py::value_error(fmt::format(
        "Volume.from_numpy: a volume is a 3-D array; this one has {} dimensions",
        a.ndim()));
  const ScalarType type = scalarTypeOf(a);
  if (!(a.flags() & (py::array::c_style | py::array::f_style)))
    throw py::value_error(
        "Volume.from_numpy: the array is not contiguous (a strided view or slice); "
        "pass np.ascontiguousarray(a)");
  int axis_of[3];  // the array axis of x, y and z
  if (axes == "xyz") axis_of[0] = 0, axis_of[1] = 1, axis_of[2] = 2;
  else if (axes == "zyx") axis_of[0] = 2, axis_of[1] = 1, axis_of[2] = 0;
  else
    throw py::value_error(fmt::format(
        "Volume.from_numpy: axes '{}' is not 'xyz' (a[x, y, z]) or 'zyx' (a[z, y, x])",
        axes));
  Dims d{};
  for (int i = 0; i < 3; ++i) {
    const py::ssize_t n = a.shape(axis_of[i]);
    if (n < 1 || n > (1 << 24))
      throw py::value_error(fmt::format(
          "Volume.from_numpy: shape {} has an axis of {} voxels; each must be 1..{}",
          py::str(a.attr("shape")).cast<std::string>(), n, 1 << 24));
    d[i] = static_cast<int>(n);
  }
  const std::uint64_t bytes = static_cast<std::uint64_t>(a.nbytes());
  // The volume, its float copy and the classification's fields: about 3× the array's
  // float size; refused here rather than failing half-way through a render.
  checkMemoryBudget(bytes + 2 * static_cast<std::uint64_t>(a.size()) * 4,
                    defaultMemoryBudget(),
                    fmt::format("Volume.from_numpy: a {}×{}×{} volume", d[0], d[1], d[2]));
  if (type == ScalarType::kFloat32)
    if (const py::ssize_t i = firstNonFinite(a); i >= 0)
      throw py::value_error(fmt::format(
          "Volume.from_numpy: the array holds a NaN or Inf (at flat index {} in memory "
          "order); voxels must be finite",
          i));
  const auto [sx, sy, sz] = spacing;
  const std::string source = fmt::format("numpy array ({}×{}×{} {}, axes {})", d[0], d[1],
                                         d[2], toString(type), axes);
  std::vector<std::byte> voxels = voxelsXFastest(a, axis_of, d);
  return PyVolume{std::make_shared<const Volume>(d, glm::dvec3(sx, sy, sz), type,
                                                 std::move(voxels), source)};
}

}  // namespace

void bindVolume(py::module_& m) {
  py::class_<PyVolume>(m, "Volume", "A regular grid of scalars or labels, x fastest.")
      .def_static(
          "from_numpy",
          [](const py::object& array, std::tuple<double, double, double> spacing,
             const std::string& axes) {
            const py::array a = py::array::ensure(array);
            if (!a) throw py::value_error("Volume.from_numpy: expected a numpy array");
            try {
              return fromNumpy(a, spacing, axes);
            } catch (const Error& e) {
              throw py::value_error(e.what());  // a bad argument (spacing, size), not a bad file
            }
          },
          py::arg("array"), py::arg("spacing") = std::make_tuple(1.0, 1.0, 1.0),
          py::arg("axes") = "xyz",
          "A volume from a 3-D uint8, uint16, int16 or float32 array (C or Fortran order); "
          "`spacing` is the voxel size along x, y, z; `axes` names the array's axes: 'xyz' "
          "(a[x, y, z]) or 'zyx' (a[z, y, x]). Label maps are volumes too: the scene's transfer "
          "function says which. Raises ValueError for anything else.")
      .def_property_readonly("dims",
                             [](const PyVolume& v) {
                               const Dims& d = v.volume->dims();
                               return py::make_tuple(d[0], d[1], d[2]);
                             },
                             "Voxels along x, y, z.")
      .def_property_readonly("spacing",
                             [](const PyVolume& v) {
                               const glm::dvec3 s = v.volume->spacing();
                               return py::make_tuple(s.x, s.y, s.z);
                             })
      .def_property_readonly("dtype", [](const PyVolume& v) { return toString(v.volume->type()); })
      .def_property_readonly("value_range",
                             [](const PyVolume& v) {
                               const auto [lo, hi] = v.volume->valueRange();
                               return py::make_tuple(lo, hi);
                             })
      .def("__repr__", [](const PyVolume& v) { return "<svr.Volume " + v.volume->source() + ">"; });
}

}  // namespace svr::python
