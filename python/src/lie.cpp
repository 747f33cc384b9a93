// legkit.lie: SO3, SE3, SE23, SEK3 (K at run time) and the IMU model of lie/, header-only C++.
// bindGroup<G> binds the API the four groups share; the helpers at the top convert arguments and
// results under the rules of the module docstring (kModuleDoc), so no method checks on its own.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>

#include "arrays.hpp"
#include "bindings.hpp"
#include "lie/lie.hpp"

namespace legkit::python {

namespace py = pybind11;

// An array argument, taken as Python passed it (read<T> below checks and converts it), under a
// name that help() can show.
struct ArrayArg {
  pybind11::handle h;
  operator pybind11::handle() const { return h; }
};

}  // namespace legkit::python

template <>
struct pybind11::detail::type_caster<legkit::python::ArrayArg> {
  PYBIND11_TYPE_CASTER(legkit::python::ArrayArg, const_name("numpy.ndarray[numpy.float64]"));
  bool load(handle src, bool) {
    value.h = src;
    return true;
  }
};

namespace legkit::python {

namespace {

constexpr int kMaxK = 8;  // as the InEKF's state lie::SEKd<double, 8>: v, p and up to 6 feet
using SO3 = lie::SO3d;
using SE3 = lie::SE3d;
using SE23 = lie::SE23d;
using SEK3 = lie::SEKd<double, kMaxK>;
using Vector3 = Eigen::Vector3d;

constexpr const char* kModuleDoc =
    R"(SO(3), SE(3), SE_2(3), SE_K(3) and the IMU model of lie/ (chapter 00).

The same header-only C++ as the kit, with its names and conventions:
  SO3   rotations R (3x3); tangent phi (3,), a rotation vector in rad (axis times angle)
  SE3   poses (R, t), K = 1; tangent (phi, rho) (6,)
  SE23  extended poses (R, v, p) of the InEKF, K = 2; tangent (phi, rho_v, rho_p) (9,)
  SEK3  (R, c_1..c_K) with K chosen at run time, 0 <= K <= 8 (v, p and up to 6 feet)
  imu   propagate, phi, phiWithBias: the exact IMU dynamics and transition of the InEKF error
Tangents put the rotation FIRST (phi, rho_1, ..., rho_K), as in the InEKF literature (Sophus and
manif put the translation first for SE(3)). Jacobians follow manif (Sola et al. 2018):
  Exp(xi + d) = Exp(xi) Exp(Jr(xi) d) = Exp(Jl(xi) d) Exp(xi).

Arguments. An array argument must be a NumPy array of dtype float64: any other dtype (float32,
int, complex, ...) raises TypeError instead of being cast. A list or tuple of numbers is
converted (it has no dtype to lose). A wrong shape raises ValueError naming the argument and the
shape expected, a NaN or inf raises ValueError "... is not finite" (fromMatrix and Log_batch
report it with the C++ message instead). A matrix that is not in the group raises
legkit.lie.NotInGroup, a ValueError carrying the C++ message; the other C++ errors arrive as
ValueError (std::invalid_argument) or IndexError (std::out_of_range) with their message.

Copies. A group object owns its C++ value. Single-element calls copy their array arguments
(3 to 121 doubles, any strides) into Eigen fixed-size types and return new C-contiguous arrays
(matrix(), Log(), Adj(), the Jacobians, ...): no returned array shares memory with a group
object or with an argument. The batched calls Exp_batch and Log_batch read their input in
place when it is a C-contiguous float64 array (otherwise after one contiguous copy), write one
new array, and loop in C++ with the GIL released.)";

// Argument conversion ----------------------------------------------------------------------

// A column count K for the run-time group, checked here: SEK3::Random and imu::phi size their
// stack storage by K before the C++ checks it.
Eigen::Index columnCount(Eigen::Index K) {
  if (K < 0 || K > kMaxK) {
    throw py::value_error("K = " + std::to_string(K) + ": SEK3 holds 0 to " +
                          std::to_string(kMaxK) + " columns");
  }
  return K;
}

double finite(double x, const char* name) {
  if (!std::isfinite(x)) throw py::value_error(std::string(name) + " is not finite");
  return x;
}

// An (N, inner...) batch, read in place when C-contiguous float64.
Array readBatch(py::handle h, const char* name, std::initializer_list<py::ssize_t> inner) {
  Array a = float64Array(h, name);
  bool ok = a.ndim() == py::ssize_t(inner.size()) + 1;
  std::string expected = "(N";
  py::ssize_t d = 1;
  for (const py::ssize_t n : inner) {
    ok = ok && a.shape(d++) == n;
    expected += ", " + std::to_string(n);
  }
  if (!ok) {
    throw py::value_error(std::string(name) + ": expected shape " + expected + "), got " +
                          shapeText(a));
  }
  return a;
}

// The tangent argument of group G (SO3 calls it phi).
template <typename G>
constexpr const char* kTangentName = std::is_same_v<G, lie::SO3d> ? "phi" : "xi";

template <typename G>
typename G::Tangent readTangent(py::handle h, const char* name = kTangentName<G>) {
  return read<typename G::Tangent>(h, name);
}

// Results -----------------------------------------------------------------------------------

template <typename T>
py::object toPython(const T& value) {
  if constexpr (std::is_base_of_v<Eigen::EigenBase<T>, T>) {
    return toArray(value);
  } else {
    return py::cast(value);
  }
}

// value, or (value, J...) when the caller passed jacobians=True.
template <typename T, typename... Jacobians>
py::object withJacobians(bool jacobians, const T& value, const Jacobians&... J) {
  if (!jacobians) return toPython(value);
  return py::make_tuple(toPython(value), toArray(J)...);
}

template <typename J>
J* wanted(bool jacobians, J& J_out) {
  return jacobians ? &J_out : nullptr;
}

// Docstrings: the C++ comments, with the unit of each quantity ------------------------------

struct Docs {
  const char *exp, *log, *act, *adj, *ad, *jr, *jl, *jrInv, *jlInv, *hat, *vee, *matrix, *random;
};

constexpr Docs kSO3Docs{
    R"(Exp(phi, *, jacobians=False) -> SO3, or (SO3, Jr) with jacobians=True.

Rodrigues: Exp(phi) = I + G_1 [phi]x + G_2 [phi]x^2, G_1 = sin(theta)/theta,
G_2 = (1 - cos theta)/theta^2, theta = |phi|. phi: (3,) rotation vector in rad (axis times
angle). The Jacobian is the right Jacobian Jr(phi): Exp(phi + d) = Exp(phi) Exp(Jr(phi) d).)",
    R"(Log(*, jacobians=False) -> phi (3,), or (phi, JrInv(phi)) with jacobians=True.

The rotation vector in rad, |phi| <= pi (at pi, phi and -phi are the same rotation). Read off
the matrix: the angle from whichever asin is well conditioned, the axis from the skew part (near
pi from the symmetric part); accurate at every angle, no atan2, no quaternion. The Jacobian
d Log(X Exp(d))/dd at d = 0 is JrInv(phi).)",
    R"(act(x, *, jacobians=False) -> R x (3,), or (R x, J_this, J_x) with jacobians=True.

x: (3,) point. J_this = -R [x]x (right perturbation of the rotation), J_x = R. X * x is the same.)",
    "Adj() -> (3, 3): the adjoint Ad_X = R, X Exp(phi) X^-1 = Exp(R phi).",
    "ad(phi) -> (3, 3): the small adjoint ad_phi = [phi]x.",
    R"(Jr(phi) -> (3, 3): the right Jacobian I - G_2 [phi]x + G_3 [phi]x^2.

Exp(phi + d) = Exp(phi) Exp(Jr(phi) d); phi in rad.)",
    R"(Jl(phi) -> (3, 3): the left Jacobian Jr(-phi) = R Jr(phi), R = Exp(phi).

Exp(phi + d) = Exp(Jl(phi) d) Exp(phi); also Gamma_1(phi) of the InEKF literature.)",
    "JrInv(phi) -> (3, 3): the inverse of Jr(phi), in closed form (JlInv(-phi)).",
    R"(JlInv(phi) -> (3, 3): the inverse of Jl(phi) in closed form,
I - [phi]x/2 + D [phi]x^2, D = (1 - (theta/2) cot(theta/2))/theta^2.)",
    "hat(phi) -> (3, 3): [phi]x, so that hat(phi) @ x = cross(phi, x).",
    "vee(M) -> (3,): (M[2,1], M[0,2], M[1,0]), the inverse of hat (M is not checked to be skew).",
    "matrix() -> (3, 3): the rotation matrix R (a new array).",
    R"(Random(seed) -> SO3: a uniformly distributed rotation (Haar measure), from a normalised
4-D Gaussian quaternion drawn by std::mt19937(seed).)",
};

constexpr Docs kSEK3Docs{
    R"(Exp(xi, *, jacobians=False) -> group, or (group, Jr) with jacobians=True.

Exp(phi, rho_i) = (Exp(phi), Jl(phi) rho_i), xi = (phi, rho_1, ..., rho_K): the rotation FIRST,
in rad, then one 3-vector per column, in the unit of the column (m, m/s). The Jacobian is the
right Jacobian Jr(xi): Exp(xi + d) = Exp(xi) Exp(Jr(xi) d).)",
    R"(Log(*, jacobians=False) -> xi (3+3K,), or (xi, JrInv(xi)) with jacobians=True.

phi = Log(R) as SO3.Log (|phi| <= pi), rho_i = Jl(phi)^-1 c_i. The Jacobian
d Log(X Exp(d))/dd at d = 0 is JrInv(xi).)",
    R"(act(x, i=0, *, jacobians=False) -> R x + c_i (3,), or (y, J_this, J_x).

Column i plays the translation (SE3: i = 0, t; SE23: i = 1 is the position p). x: (3,) point.
J_this (3, 3+3K): -R [x]x in the rotation block, R in the block of column i; J_x = R.)",
    R"(Adj() -> (3+3K, 3+3K): the adjoint Ad_X = [[R, 0], [[c_i]x R, R]] (block lower-triangular),
X Exp(xi) X^-1 = Exp(Ad_X xi).)",
    "ad(xi) -> (3+3K, 3+3K): the small adjoint [[[phi]x, 0], [[rho_i]x, [phi]x]].",
    "Jr(xi) -> (3+3K, 3+3K): the right Jacobian Jl(-xi): Exp(xi + d) = Exp(xi) Exp(Jr(xi) d).",
    R"(Jl(xi) -> (3+3K, 3+3K): the left Jacobian [[Jl(phi), 0], [Q(phi, rho_i), Jl(phi)]],
Q Barfoot's SE(3) coupling block; Exp(xi + d) = Exp(Jl(xi) d) Exp(xi).)",
    "JrInv(xi) -> (3+3K, 3+3K): the inverse of Jr(xi) in closed form (JlInv(-xi)).",
    R"(JlInv(xi) -> (3+3K, 3+3K): the inverse of Jl(xi) in closed form,
[[Jl(phi)^-1, 0], [-Jl(phi)^-1 Q Jl(phi)^-1, Jl(phi)^-1]].)",
    "hat(xi) -> (3+K, 3+K): [[[phi]x, rho_1 ... rho_K], [0, 0]], the Lie algebra element.",
    R"(vee(M) -> (3+3K,): the inverse of hat, reading the skew block and the top of the last K
columns (M is not checked to be in the Lie algebra).)",
    "matrix() -> (3+K, 3+K): [[R, c_1 ... c_K], [0, I]] (a new array).",
    R"(Random(seed, scale=1.0) -> group: a uniformly random rotation (SO3.Random) with columns
drawn from N(0, scale^2 I), by std::mt19937(seed).)",
};

// The API common to the four groups -----------------------------------------------------------

template <typename G>
void bindGroup(py::class_<G>& cls, const char* name) {
  using Tangent = typename G::Tangent;
  using Jacobian = typename G::Jacobian;
  using Matrix = typename G::Matrix;
  constexpr bool isSO3 = std::is_same_v<G, SO3>;
  constexpr bool dynamic = Tangent::RowsAtCompileTime == Eigen::Dynamic;
  constexpr const char* xiName = kTangentName<G>;
  const Docs& doc = isSO3 ? kSO3Docs : kSEK3Docs;

  cls.def_static(
         "Exp",
         [](ArrayArg xi, bool jacobians) {
           Jacobian J;
           const G X = G::Exp(readTangent<G>(xi), wanted(jacobians, J));
           return withJacobians(jacobians, X, J);
         },
         py::arg(xiName), py::kw_only(), py::arg("jacobians") = false, doc.exp)
      .def(
          "Log",
          [](const G& X, bool jacobians) {
            Jacobian J;
            const Tangent xi = X.Log(wanted(jacobians, J));
            return withJacobians(jacobians, xi, J);
          },
          py::kw_only(), py::arg("jacobians") = false, doc.log)
      .def(
          "inverse",
          [](const G& X, bool jacobians) {
            Jacobian J;
            const G Xi = X.inverse(wanted(jacobians, J));
            return withJacobians(jacobians, Xi, J);
          },
          py::kw_only(), py::arg("jacobians") = false,
          "inverse(*, jacobians=False) -> X^-1, or (X^-1, -Adj()) with jacobians=True.")
      .def(
          "compose",
          [](const G& X, const G& Y, bool jacobians) {
            Jacobian JX, JY;
            const G XY = X.compose(Y, wanted(jacobians, JX), wanted(jacobians, JY));
            return withJacobians(jacobians, XY, JX, JY);
          },
          py::arg("other"), py::kw_only(), py::arg("jacobians") = false,
          R"(compose(other, *, jacobians=False) -> X Y, or (X Y, J_this, J_other).

The group product (X * Y is the same). J_this = Adj of Y^-1, J_other = I (right perturbations).)")
      .def(
          "__mul__", [](const G& X, const G& Y) { return X * Y; }, py::is_operator())
      .def(
          "Adj", [](const G& X) { return toArray(X.Adj()); }, doc.adj)
      .def(
          "matrix", [](const G& X) { return toArray(X.matrix()); }, doc.matrix)
      .def(
          "rplus", [](const G& X, ArrayArg tau) { return X.rplus(readTangent<G>(tau, "tau")); },
          py::arg("tau"), "rplus(tau) -> X Exp(tau): tau in the body (right) frame.")
      .def(
          "lplus", [](const G& X, ArrayArg tau) { return X.lplus(readTangent<G>(tau, "tau")); },
          py::arg("tau"), "lplus(tau) -> Exp(tau) X: tau in the world (left) frame.")
      .def(
          "rminus", [](const G& Y, const G& X) { return toArray(Y.rminus(X)); }, py::arg("X"),
          "Y.rminus(X) -> Log(X^-1 Y), so X.rplus(it) = Y.")
      .def(
          "lminus", [](const G& Y, const G& X) { return toArray(Y.lminus(X)); }, py::arg("X"),
          "Y.lminus(X) -> Log(Y X^-1), so X.lplus(it) = Y.")
      .def(
          "interpolate",
          [](const G& X, const G& Y, double t) { return X.interpolate(Y, finite(t, "t")); },
          py::arg("other"), py::arg("t"),
          "interpolate(other, t) -> X Exp(t Log(X^-1 Y)): geodesic, t = 0 gives X, t = 1 Y.")
      .def("isApprox", &G::isApprox, py::arg("other"), py::arg("tol") = 1e-10,
           "isApprox(other, tol=1e-10): every entry of R within tol (columns: tol times their "
           "scale max(1, max |c|)).")
      .def("normalized", &G::normalized,
           "normalized() -> the nearest rotation (Frobenius norm, from the SVD), removing "
           "rounding drift; columns unchanged.")
      .def_static(
          "hat", [](ArrayArg xi) { return toArray(G::hat(readTangent<G>(xi))); }, py::arg(xiName),
          doc.hat)
      .def_static(
          "vee",
          [](ArrayArg M) {
            const Matrix m = read<Matrix>(M, "M");
            if (m.rows() != m.cols() || m.rows() < 3) {
              throw py::value_error("M: expected a square matrix of size 3+K, got " +
                                    std::to_string(m.rows()) + "x" + std::to_string(m.cols()));
            }
            return toArray(G::vee(m));
          },
          py::arg("M"), doc.vee)
      .def_static(
          "ad", [](ArrayArg xi) { return toArray(G::ad(readTangent<G>(xi))); }, py::arg(xiName),
          doc.ad)
      .def_static(
          "Jr", [](ArrayArg xi) { return toArray(G::Jr(readTangent<G>(xi))); }, py::arg(xiName),
          doc.jr)
      .def_static(
          "Jl", [](ArrayArg xi) { return toArray(G::Jl(readTangent<G>(xi))); }, py::arg(xiName),
          doc.jl)
      .def_static(
          "JrInv", [](ArrayArg xi) { return toArray(G::JrInv(readTangent<G>(xi))); },
          py::arg(xiName), doc.jrInv)
      .def_static(
          "JlInv", [](ArrayArg xi) { return toArray(G::JlInv(readTangent<G>(xi))); },
          py::arg(xiName), doc.jlInv)
      .def_static(
          "fromMatrix",
          [](ArrayArg M, double tol) { return G::fromMatrix(read<Matrix>(M, "M", false), tol); },
          py::arg("M"), py::arg("tol") = 1e-9,
          "fromMatrix(M, tol=1e-9) -> the group element of matrix M, checked as in C++: finite, "
          "R orthonormal to tol with determinant +1 (and the last K rows [0 | I]), otherwise "
          "NotInGroup saying what is wrong.")
      .def("__repr__", [name](const G& X) {
        const Eigen::IOFormat format(Eigen::StreamPrecision, Eigen::DontAlignCols, ", ", ", ", "[",
                                     "]", "[", "]");
        std::ostringstream os;
        os << name << "(" << X.matrix().format(format) << ")";
        return os.str();
      });

  // Identity and Random; the run-time group takes its K.
  if constexpr (dynamic) {
    cls.def_static("Identity", &G::Identity, py::arg("K"), "Identity(K): K columns, all zero.")
        .def_static(
            "Random",
            [](Eigen::Index K, std::uint32_t seed, double scale) {
              std::mt19937 gen(seed);
              return G::Random(gen, scale, columnCount(K));
            },
            py::arg("K"), py::arg("seed"), py::arg("scale") = 1.0,
            "Random(K, seed, scale=1.0): as SE23.Random, with K columns (the same draws: "
            "SEK3.Random(2, s) equals SE23.Random(s)).");
  } else {
    cls.def(py::init<>(), "The identity.")
        .def_static(
            "Identity", [] { return G::Identity(); }, "The identity.");
    if constexpr (isSO3) {
      cls.def_static(
          "Random",
          [](std::uint32_t seed) {
            std::mt19937 gen(seed);
            return G::Random(gen);
          },
          py::arg("seed"), doc.random);
    } else {
      cls.def_static(
          "Random",
          [](std::uint32_t seed, double scale) {
            std::mt19937 gen(seed);
            return G::Random(gen, scale);
          },
          py::arg("seed"), py::arg("scale") = 1.0, doc.random);
    }
    cls.attr("DoF") = int(G::DoF);

    // Batched Exp and Log: the loop in C++, without the GIL, on the caller's array when it is
    // C-contiguous float64. Row i equals the single call on row i bit for bit (same code).
    static constexpr int dof = Tangent::RowsAtCompileTime, dim = Matrix::RowsAtCompileTime;
    using MatrixRowMajor = Eigen::Matrix<double, dim, dim, Eigen::RowMajor>;
    const std::string rows = "(N, " + std::to_string(dof) + ")",
                      matrices = "(N, " + std::to_string(dim) + ", " + std::to_string(dim) + ")";
    const std::string expBatchDoc =
        "Exp_batch(" + std::string(xiName) + ": " + rows + ") -> " + matrices + ": Exp(" + xiName +
        "[i]).matrix() for every row, equal to the single call bit for bit.\n\nLoops " +
        "in C++ without the GIL; reads " + xiName + " in place when it is C-contiguous float64 " +
        "(else after one copy), writes one new array.";
    const std::string logBatchDoc =
        "Log_batch(M: " + matrices + ", tol=1e-9) -> " + rows + ": fromMatrix(M[i], tol).Log() " +
        "for every matrix, equal to the single calls bit for bit; NotInGroup names the first " +
        "matrix that is not in the group.\n\nLoops in C++ without the GIL; reads M in place " +
        "when it is C-contiguous float64 (else after one copy), writes one new array.";
    cls.def_static(
           "Exp_batch",
           [](ArrayArg xi) {
             const Array in = readBatch(xi, xiName, {dof});
             const py::ssize_t n = in.shape(0);
             py::array_t<double> out({n, py::ssize_t(dim), py::ssize_t(dim)});
             const double* src = in.data();
             double* dst = out.mutable_data();
             py::ssize_t bad = -1;
             {
               py::gil_scoped_release release;
               for (py::ssize_t i = 0; i < n; ++i) {
                 const Tangent x = Eigen::Map<const Tangent>(src + i * dof);
                 if (!x.allFinite()) {
                   bad = i;
                   break;
                 }
                 Eigen::Map<MatrixRowMajor>(dst + i * dim * dim) = G::Exp(x).matrix();
               }
             }
             if (bad >= 0) {
               throw py::value_error(std::string(xiName) + "[" + std::to_string(bad) +
                                     "] is not finite");
             }
             return out;
           },
           py::arg(xiName), expBatchDoc.c_str())
        .def_static(
            "Log_batch",
            [](ArrayArg M, double tol) {
              const Array in = readBatch(M, "M", {dim, dim});
              const py::ssize_t n = in.shape(0);
              py::array_t<double> out({n, py::ssize_t(dof)});
              const double* src = in.data();
              double* dst = out.mutable_data();
              {
                py::gil_scoped_release release;  // back before the exception reaches Python
                for (py::ssize_t i = 0; i < n; ++i) {
                  try {
                    const G X =
                        G::fromMatrix(Eigen::Map<const MatrixRowMajor>(src + i * dim * dim), tol);
                    Eigen::Map<Tangent>(dst + i * dof) = X.Log();
                  } catch (const lie::NotInGroup& e) {
                    throw lie::NotInGroup("M[" + std::to_string(i) + "]: " + e.what());
                  }
                }
              }
              return out;
            },
            py::arg("M"), py::arg("tol") = 1e-9, logBatchDoc.c_str());
  }
}

// The column accessors of SE3, SE23 and SEK3.
template <typename G>
void bindColumns(py::class_<G>& cls) {
  using Columns = typename G::Columns;
  if constexpr (!G::kDynamic) cls.attr("K") = G::K;
  cls.def(py::init([](const SO3& R, ArrayArg C) { return G(R, read<Columns>(C, "C")); }),
          py::arg("R"), py::arg("C"),
          "(R: SO3, C): rotation R and columns C, shape (3, K) (SE3: (3,), the translation).")
      .def(
          "act",
          [](const G& X, ArrayArg x, Eigen::Index i, bool jacobians) {
            Eigen::Matrix<double, 3, G::DoF, 0, 3, G::MaxDoF> JX;
            Eigen::Matrix3d Jx;
            const Vector3 y =
                X.act(read<Vector3>(x, "x"), i, wanted(jacobians, JX), wanted(jacobians, Jx));
            return withJacobians(jacobians, y, JX, Jx);
          },
          py::arg("x"), py::arg("i") = 0, py::kw_only(), py::arg("jacobians") = false,
          kSEK3Docs.act)
      .def(
          "R", [](const G& X) { return toArray(X.R()); }, "R() -> (3, 3): the rotation matrix.")
      .def("rotation", &G::rotation, "rotation() -> SO3: the rotation.")
      .def(
          "columns", [](const G& X) { return toArray(X.columns()); },
          "columns() -> (3, K): c_1 .. c_K (SE3: (3,)); [m] for positions, [m/s] for v.")
      .def(
          "col",
          [](const G& X, Eigen::Index i) {
            if (i < 0 || i >= X.numCols()) {
              throw py::index_error("no such column: " + std::to_string(i));
            }
            return toArray(Vector3(X.col(i)));
          },
          py::arg("i"), "col(i) -> (3,): column i (SE23: 0 is the velocity v, 1 the position p).")
      .def("numCols", &G::numCols, "numCols() -> K.")
      .def("dof", &G::dof, "dof() -> 3 + 3K, the size of a tangent.");
}

// The IMU model, for SE23 and SEK3 (overloads of one Python function each).
template <typename G>
void bindImu(py::module_& imu, bool withDoc) {
  imu.def(
      "propagate",
      [](const G& X, ArrayArg w, ArrayArg a, ArrayArg g, double dt) {
        return lie::imu::propagate(X, read<Vector3>(w, "w"), read<Vector3>(a, "a"),
                                   read<Vector3>(g, "g"), finite(dt, "dt"));
      },
      py::arg("X"), py::arg("w"), py::arg("a"), py::arg("g"), py::arg("dt"),
      withDoc ? R"(propagate(X, w, a, g, dt) -> X at t + dt (same type as X: SE23 or SEK3, K >= 2).

Exact propagation of X = (R, v, p, d_1..d_n) over dt [s] with constant, bias-corrected body rate
w [rad/s] and specific force a [m/s^2] (body frame), gravity g [m/s^2] in the world frame, e.g.
(0, 0, -9.81):  dR/dt = R [w]x, dv/dt = R a + g, dp/dt = v, dd_i/dt = 0.
Solved in closed form as X_{k+1} = Gamma_g f(X_k) Upsilon (Barrau & Bonnabel 2017). There are no
bias arguments: subtract the biases from w and a first.)"
              : "");
  imu.def(
      "phiWithBias",
      [](const G& X_next, ArrayArg w, ArrayArg a, ArrayArg g, double dt) {
        return toArray(lie::imu::phiWithBias(X_next, read<Vector3>(w, "w"), read<Vector3>(a, "a"),
                                             read<Vector3>(g, "g"), finite(dt, "dt")));
      },
      py::arg("X_next"), py::arg("w"), py::arg("a"), py::arg("g"), py::arg("dt"),
      withDoc ? R"(phiWithBias(X_next, w, a, g, dt) -> (3+3K+6, 3+3K+6).

Phi of the right-invariant error augmented with the bias error zeta = b_hat - b (gyro first,
then accel): [[Phi, -Ad_{X_next} J_u], [0, I_6]], X_next = propagate(X, w, a, g, dt) the
propagated estimate and J_u the right Jacobian of the increment Upsilon with respect to
u = (w, a). To first order xi_{k+1} = Phi xi_k - Ad_{X_next} J_u zeta, exact for piecewise-
constant input (not the first-order I + A dt). w [rad/s], a [m/s^2]: the bias-corrected body
inputs; g [m/s^2] world gravity; dt [s].)"
              : "");
}

}  // namespace

void bindLie(py::module_& m) {
  m.doc() = kModuleDoc;
  py::register_exception<lie::NotInGroup>(m, "NotInGroup", PyExc_ValueError);

  py::class_<SO3> so3(m, "SO3", R"(SO(3): rotations of R^3, stored as a 3x3 rotation matrix R.

Tangent: a rotation vector phi in rad, hat(phi) = [phi]x. In the IMU model R maps the body frame
to the world frame. Jacobians (manif): Exp(phi + d) = Exp(phi) Exp(Jr(phi) d).)");
  bindGroup(so3, "SO3");
  so3.def(
         "act",
         [](const SO3& X, ArrayArg x, bool jacobians) {
           Eigen::Matrix3d JX, Jx;
           const Vector3 y =
               X.act(read<Vector3>(x, "x"), wanted(jacobians, JX), wanted(jacobians, Jx));
           return withJacobians(jacobians, y, JX, Jx);
         },
         py::arg("x"), py::kw_only(), py::arg("jacobians") = false, kSO3Docs.act)
      .def(
          "__mul__", [](const SO3& X, ArrayArg x) { return toArray(X * read<Vector3>(x, "x")); },
          py::is_operator())
      .def(
          "quaternion",
          [](const SO3& X) {
            const Eigen::Quaterniond q = X.quaternion();
            return toArray(Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()));
          },
          "quaternion() -> (w, x, y, z), unit norm, the sign Eigen gives (q and -q are the same "
          "rotation).")
      .def_static(
          "fromQuaternion",
          [](ArrayArg q) {
            const Eigen::Vector4d v = read<Eigen::Vector4d>(q, "q");
            if (v.squaredNorm() == 0)
              throw py::value_error("q: the zero quaternion is no rotation");
            return SO3::fromQuaternion(Eigen::Quaterniond(v(0), v(1), v(2), v(3)));
          },
          py::arg("q"), "fromQuaternion(q: (w, x, y, z)) -> SO3, normalising q first.");

  py::class_<SE3> se3(m, "SE3", R"(SE(3): poses (R, t), K = 1 column, the matrix [[R, t], [0, 1]].

Tangent xi = (phi, rho): rotation FIRST [rad], then rho [m] (manif and Sophus put rho first).
X * x = R x + t.)");
  bindGroup(se3, "SE3");
  bindColumns(se3);
  se3.def(
         "translation", [](const SE3& X) { return toArray(X.translation()); },
         "translation() -> t (3,), column 0 [m].")
      .def(
          "__mul__", [](const SE3& X, ArrayArg x) { return toArray(X.act(read<Vector3>(x, "x"))); },
          py::is_operator());

  py::class_<SE23> se23(m, "SE23", R"(SE_2(3): the extended pose (R, v, p) of the InEKF, K = 2.

Matrix [[R, v, p], [0, I_2]]: R body to world, v [m/s] and p [m] in the world frame. Tangent
xi = (phi, rho_v, rho_p), 9, rotation first [rad].)");
  bindGroup(se23, "SE23");
  bindColumns(se23);

  py::class_<SEK3> sek3(m, "SEK3", R"(SE_K(3) with K chosen at run time, 0 <= K <= 8 (MaxK).

(R, c_1..c_K), matrix [[R, c_1 ... c_K], [0, I_K]], the group law the matrix product; the InEKF
state (R, v, p, d_1..d_n) with up to 6 feet. SEK3(K) is the identity with K columns;
appendColumn and removeColumn change K (a contact made or lost). Every operation gives the same
bits as SE3 (K = 1) or SE23 (K = 2); operands must have the same K.)");
  bindGroup(sek3, "SEK3");
  bindColumns(sek3);
  sek3.def(py::init<Eigen::Index>(), py::arg("K"), "SEK3(K): the identity with K columns.")
      .def(
          "appendColumn", [](SEK3& X, ArrayArg c) { X.appendColumn(read<Vector3>(c, "c")); },
          py::arg("c"), "appendColumn(c): add a column c (3,) (a new contact point), in place.")
      .def("removeColumn", &SEK3::removeColumn, py::arg("i"),
           "removeColumn(i): remove column i (a lost contact), in place; later columns move down.");
  sek3.attr("MaxK") = kMaxK;

  auto imu = m.def_submodule("imu", R"(The IMU model of lie/imu_dynamics.hpp on SE_{2+n}(3).

State X = (R, v, p, d_1..d_n): columns 0 and 1 are velocity and position, the rest contact
points. Right-invariant error eta = X_hat X^-1, xi = Log(eta).)");
  bindImu<SE23>(imu, true);
  bindImu<SEK3>(imu, false);
  imu.def(
      "phi",
      [](Eigen::Index K, ArrayArg g, double dt) {
        return toArray(
            lie::imu::phi<SEK3>(columnCount(K), read<Vector3>(g, "g"), finite(dt, "dt")));
      },
      py::arg("K"), py::arg("g"), py::arg("dt"),
      R"(phi(K, g, dt) -> Phi (3+3K, 3+3K), 2 <= K <= 8: the transition of the right-invariant
error for a perfect IMU (no bias states), xi_{k+1} = Phi xi_k, exact (log-linearity: the same
input for estimate and truth, however large the error):
  Phi = Ad_{Gamma_g} Df = I + A dt + A^2 dt^2/2,
  A = [[0, 0, 0], [[g]x, 0, 0], [0, I, 0]] on (phi, v, p), zero rows for the contacts.
Depends only on g [m/s^2, world frame] and dt [s].)");
}

}  // namespace legkit::python
