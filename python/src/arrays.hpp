// Array arguments from Python, checked under one rule for the whole package (legkit.lie's
// docstring states it): a NumPy array must be float64 (another dtype is a TypeError naming the
// argument, never a silent cast), a list or tuple of numbers is converted, a wrong shape is a
// ValueError naming the argument and the shape expected. Small fixed-size values are copied into
// the Eigen types the C++ takes.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <string>

namespace legkit::python {

namespace py = pybind11;

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

inline std::string shapeText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// A float64 array as it is (no copy when C-contiguous), or a sequence of numbers converted.
inline Array float64Array(py::handle h, const char* name) {
  if (py::isinstance<py::array>(h) && !py::isinstance<py::array_t<double>>(h)) {
    throw py::type_error(std::string(name) + ": expected a float64 array, got dtype " +
                         std::string(py::str(h.attr("dtype"))));
  }
  Array a = Array::ensure(h);
  if (!a) {
    throw py::type_error(std::string(name) + ": expected a float64 array or numbers, got " +
                         Py_TYPE(h.ptr())->tp_name);
  }
  return a;
}

// The shape of Eigen type T as Python writes it: "(3,)", "(5, 5)", "(n,) with n <= 27".
template <typename T>
std::string expectedShape() {
  constexpr int rows = T::RowsAtCompileTime, cols = T::ColsAtCompileTime;
  const auto dim = [](int n, const char* free) {
    return n == Eigen::Dynamic ? std::string(free) : std::to_string(n);
  };
  std::string text = "(" + dim(rows, "n") + (cols == 1 ? ",)" : ", " + dim(cols, "m") + ")");
  if (rows == Eigen::Dynamic) text += " with n <= " + std::to_string(T::MaxRowsAtCompileTime);
  if (cols == Eigen::Dynamic) {
    text += (rows == Eigen::Dynamic ? ", m <= " : " with m <= ") +
            std::to_string(T::MaxColsAtCompileTime);
  }
  return text;
}

inline bool fits(py::ssize_t n, int fixed, int max) {
  return fixed == Eigen::Dynamic ? n <= max : n == fixed;
}

// Argument `name` as the Eigen type T (a vector is a 1-D array), copied, shape checked, and
// finite unless the C++ checks that itself (checkFinite = false).
template <typename T>
T read(py::handle h, const char* name, bool checkFinite = true) {
  constexpr bool vector = T::ColsAtCompileTime == 1;
  const Array a = float64Array(h, name);
  if (a.ndim() != (vector ? 1 : 2) ||
      !fits(a.shape(0), T::RowsAtCompileTime, T::MaxRowsAtCompileTime) ||
      (!vector && !fits(a.shape(1), T::ColsAtCompileTime, T::MaxColsAtCompileTime))) {
    throw py::value_error(std::string(name) + ": expected shape " + expectedShape<T>() + ", got " +
                          shapeText(a));
  }
  T value = Eigen::Map<const RowMajor>(a.data(), a.shape(0), vector ? 1 : a.shape(1));
  if (checkFinite && !value.allFinite()) {
    throw py::value_error(std::string(name) + " is not finite");
  }
  return value;
}

// A float64 array argument of ndim dimensions (any shape).
inline Array float64Array(py::handle h, const char* name, int ndim) {
  Array a = float64Array(h, name);
  if (a.ndim() != ndim) {
    throw py::value_error(std::string(name) + ": expected " + std::to_string(ndim) +
                          " dimension(s), got shape " + shapeText(a));
  }
  return a;
}

// A fixed-size R x C value (C == 1: shape (R,)), whose finiteness the C++ it goes to checks.
template <int R, int C = 1>
Eigen::Matrix<double, R, C> fixed(py::handle h, const char* name) {
  return read<Eigen::Matrix<double, R, C>>(h, name, false);
}

// A new C-contiguous array: shape (n,) for a vector, (rows, cols) otherwise.
template <typename Derived>
py::array_t<double> toArray(const Eigen::MatrixBase<Derived>& m) {
  const bool vector = Derived::ColsAtCompileTime == 1;
  py::array_t<double> out =
      vector ? py::array_t<double>(m.rows()) : py::array_t<double>({m.rows(), m.cols()});
  Eigen::Map<RowMajor>(out.mutable_data(), m.rows(), m.cols()) = m;
  return out;
}

}  // namespace legkit::python
