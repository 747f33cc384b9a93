// SE_K(3): a rotation R together with K vectors c_1..c_K of R^3 ("extended poses").
//
//        [ R  c_1 ... c_K ]
//   X =  [ 0   1        0 ]   in R^{(3+K) x (3+K)},   group law = matrix product:
//        [ 0   0  ...   1 ]   (R1, c1_i) * (R2, c2_i) = (R1 R2, R1 c2_i + c1_i).
//
// K = 1 is SE(3) (c_1 = translation), K = 2 is SE_2(3) (R, v, p) of inertial navigation, and
// K = 2 + n carries n contact points as in the contact-aided InEKF.
//
// Tangent vectors are ordered (phi, rho_1, ..., rho_K): rotation FIRST, then each column in
// order, as in the InEKF literature. (Sophus and manif put translation first for SE(3).)
//   Exp(phi, rho_i) = (Exp(phi), Jl(phi) rho_i)          Log: rho_i = Jl(phi)^-1 c_i
//   Ad_X = [[R, 0], [[c_i]_x R, R]]                      ad_xi = [[[phi], 0], [[rho_i], [phi]]]
//   Jl(xi) = [[Jl(phi), 0], [Q(phi, rho_i), Jl(phi)]]    Jr(xi) = Jl(-xi)
// where Q(phi, rho) = sum_{n,m} [phi]^n [rho] [phi]^m / (n+m+2)! is the SE(3) coupling block
// (Barfoot's Q), written here in the G coefficients of so3_series.hpp so that no term cancels:
//   Q = [rho]/2 + G_3 (P R + R P + P R P) + G_4 (P^2 R + R P^2 - 3 P R P)
//       + (G_4 - 3 G_5)/2 (P R P^2 + P^2 R P),          P = [phi], R = [rho].
// Every column couples to the rotation only, so each Jacobian is block lower-triangular.
//
// K may be a compile-time number, or Eigen::Dynamic with a compile-time bound MaxK: then the
// number of columns changes at run time (contacts made and broken) while all storage stays on
// the stack (Eigen's MaxRows/MaxCols), so an estimator step never allocates.
#pragma once

#include <Eigen/Core>
#include <random>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "lie/errors.hpp"
#include "lie/so3.hpp"

namespace lie {

template <typename Scalar_, int K_, int MaxK_ = K_>
class SEK3 {
 public:
  using Scalar = Scalar_;
  static constexpr bool kDynamic = K_ == Eigen::Dynamic;
  static constexpr int K = K_;
  static constexpr int MaxK = MaxK_;
  static_assert(kDynamic ? MaxK >= 1 : (K >= 1 && MaxK == K),
                "SEK3<S, K>: K >= 1, or SEK3<S, Eigen::Dynamic, MaxK> with MaxK >= 1");
  static constexpr int DoF = kDynamic ? Eigen::Dynamic : 3 + 3 * K;
  static constexpr int MaxDoF = 3 + 3 * MaxK;
  static constexpr int Dim = kDynamic ? Eigen::Dynamic : 3 + K;
  static constexpr int MaxDim = 3 + MaxK;

  using SO3Type = SO3<Scalar>;
  using Matrix3 = lie::Matrix3<Scalar>;
  using Vector3 = lie::Vector3<Scalar>;
  using Columns = Eigen::Matrix<Scalar, 3, K, Eigen::ColMajor, 3, MaxK>;
  using Tangent = Eigen::Matrix<Scalar, DoF, 1, Eigen::ColMajor, MaxDoF, 1>;
  using Jacobian = Eigen::Matrix<Scalar, DoF, DoF, Eigen::ColMajor, MaxDoF, MaxDoF>;
  using AdjointMatrix = Jacobian;
  using Matrix = Eigen::Matrix<Scalar, Dim, Dim, Eigen::ColMajor, MaxDim, MaxDim>;
  using Point = Vector3;

  // Identity with K columns (for the run-time variant: with k columns).
  SEK3() : SEK3(kDynamic ? 0 : K) {}
  explicit SEK3(Eigen::Index k) : R_(Matrix3::Identity()) {
    checkColumnCount(k, "SEK3");
    C_.setZero(3, k);
  }
  SEK3(const SO3Type& R, const Columns& C) : R_(R.matrix()), C_(C) {
    checkColumnCount(C.cols(), "SEK3");
  }
  static SEK3 Identity(Eigen::Index k = kDynamic ? 0 : K) { return SEK3(k); }

  // Checked construction from a (3+K)x(3+K) matrix: throws lie::NotInGroup naming what is wrong.
  static SEK3 fromMatrix(const Matrix& M, Scalar tol = Scalar(1e-9)) {
    const Eigen::Index k = M.rows() - 3;
    if (M.rows() != M.cols() || k < 0 || k > MaxK || (!kDynamic && k != K)) {
      std::ostringstream os;
      os << "SEK3::fromMatrix: expected a square matrix of size 3+K with K "
         << (kDynamic ? "<= " : "= ") << MaxK << ", got " << M.rows() << "x" << M.cols();
      throw NotInGroup(os.str());
    }
    if (!M.allFinite()) throw NotInGroup("SEK3::fromMatrix: matrix has a NaN or inf entry");
    using std::abs;
    const auto bottom = M.bottomRows(k);
    Scalar bottomError(0);
    for (Eigen::Index r = 0; r < k; ++r) {
      for (Eigen::Index j = 0; j < 3 + k; ++j) {
        const Scalar error = abs(bottom(r, j) - Scalar(j == 3 + r ? 1 : 0));
        if (bottomError < error) bottomError = error;  // std::max, for autodiff scalars too
      }
    }
    if (!(bottomError <= tol)) {
      std::ostringstream os;
      os << "SEK3::fromMatrix: the last " << k << " rows must be [0 | I] (max error " << bottomError
         << " > tol " << tol << ")";
      throw NotInGroup(os.str());
    }
    return SEK3(SO3Type::fromMatrix(M.template topLeftCorner<3, 3>(), tol), M.topRightCorner(3, k));
  }

  // Accessors ---------------------------------------------------------------------------
  const Matrix3& R() const { return R_; }
  SO3Type rotation() const { return SO3Type(R_, typename SO3Type::Unchecked{}); }
  const Columns& columns() const { return C_; }
  auto col(Eigen::Index i) const { return C_.col(i); }
  auto col(Eigen::Index i) { return C_.col(i); }
  Eigen::Index numCols() const { return C_.cols(); }
  Eigen::Index dof() const { return 3 + 3 * C_.cols(); }

  // SE(3) spelling of the single column.
  template <int KK = K, std::enable_if_t<KK == 1, int> = 0>
  Vector3 translation() const {
    return C_.col(0);
  }

  Matrix matrix() const {
    const Eigen::Index k = numCols();
    Matrix M = Matrix::Identity(3 + k, 3 + k);
    M.template topLeftCorner<3, 3>() = R_;
    M.topRightCorner(3, k) = C_;
    return M;
  }

  // Run-time K only: add a column (a new contact) or remove column i (a lost contact).
  void appendColumn(const Vector3& c) {
    static_assert(kDynamic, "appendColumn needs SEK3<S, Eigen::Dynamic, MaxK>");
    checkColumnCount(numCols() + 1, "SEK3::appendColumn");
    C_.conservativeResize(3, numCols() + 1);
    C_.col(numCols() - 1) = c;
  }
  void removeColumn(Eigen::Index i) {
    static_assert(kDynamic, "removeColumn needs SEK3<S, Eigen::Dynamic, MaxK>");
    if (i < 0 || i >= numCols()) throw std::out_of_range("SEK3::removeColumn: no such column");
    for (Eigen::Index j = i; j + 1 < numCols(); ++j) C_.col(j) = C_.col(j + 1);
    C_.conservativeResize(3, numCols() - 1);
  }

  // Group operations ---------------------------------------------------------------------
  SEK3 operator*(const SEK3& Y) const {
    checkSameK(Y, "SEK3::operator*");
    return SEK3(R_ * Y.R_, R_ * Y.C_ + C_, Unchecked{});
  }
  SEK3 compose(const SEK3& Y, Jacobian* J_out_this = nullptr, Jacobian* J_out_Y = nullptr) const {
    if (J_out_this) *J_out_this = Y.inverse().Adj();
    if (J_out_Y) J_out_Y->setIdentity(Y.dof(), Y.dof());
    return *this * Y;
  }
  SEK3 inverse(Jacobian* J_out_this = nullptr) const {
    if (J_out_this) *J_out_this = -Adj();
    const Matrix3 Rt = R_.transpose();
    return SEK3(Rt, -Rt * C_, Unchecked{});
  }

  // Action on a point, with column i playing the translation: R x + c_i (for SE(3), i = 0).
  Point act(const Point& x, Eigen::Index i = 0,
            Eigen::Matrix<Scalar, 3, DoF, 0, 3, MaxDoF>* J_out_this = nullptr,
            Matrix3* J_out_x = nullptr) const {
    if (i < 0 || i >= numCols()) throw std::out_of_range("SEK3::act: no such column");
    if (J_out_this) {
      J_out_this->setZero(3, dof());
      J_out_this->template leftCols<3>() = -R_ * hat3(x);
      J_out_this->template middleCols<3>(3 + 3 * i) = R_;
    }
    if (J_out_x) *J_out_x = R_;
    return R_ * x + C_.col(i);
  }

  // Exp / Log ---------------------------------------------------------------------------
  static SEK3 Exp(const Tangent& xi, Jacobian* J_out_xi = nullptr) {
    const Eigen::Index k = columnsOfTangent(xi, "SEK3::Exp");
    const Vector3 phi = xi.template head<3>();
    const AngleSeries<Scalar> c(phi.squaredNorm());
    if (J_out_xi) *J_out_xi = Jr(xi);
    return SEK3(SO3Type::expMatrix(phi, c), SO3Type::Jr(-phi, c) * rhoOf(xi, k),  // Jl = Jr(-phi)
                Unchecked{});
  }

  Tangent Log(Jacobian* J_out_this = nullptr) const {
    AngleSeries<Scalar> c(Scalar(0));
    const Vector3 phi = SO3Type::logOfMatrix(R_, &c);
    Tangent xi(dof());
    xi.template head<3>() = phi;
    rhoOf(xi, numCols()).noalias() = jlInv(phi, c) * C_;
    if (J_out_this) *J_out_this = JrInv(xi);
    return xi;
  }

  static Matrix hat(const Tangent& xi) {
    const Eigen::Index k = columnsOfTangent(xi, "SEK3::hat");
    Matrix M = Matrix::Zero(3 + k, 3 + k);
    M.template topLeftCorner<3, 3>() = hat3(xi.template head<3>());
    M.topRightCorner(3, k) = rhoOf(xi, k);
    return M;
  }
  static Tangent vee(const Matrix& M) {
    const Eigen::Index k = M.cols() - 3;
    Tangent xi(3 + 3 * k);
    xi.template head<3>() = SO3Type::vee(M.template topLeftCorner<3, 3>());
    rhoOf(xi, k) = M.topRightCorner(3, k);
    return xi;
  }

  // Adjoint and small adjoint ------------------------------------------------------------
  AdjointMatrix Adj() const {
    const Eigen::Index k = numCols();
    AdjointMatrix A = AdjointMatrix::Zero(dof(), dof());
    for (Eigen::Index i = 0; i <= k; ++i) A.template block<3, 3>(3 * i, 3 * i) = R_;
    for (Eigen::Index i = 0; i < k; ++i) {
      A.template block<3, 3>(3 + 3 * i, 0).noalias() = hat3(C_.col(i)) * R_;
    }
    return A;
  }
  static AdjointMatrix ad(const Tangent& xi) {
    const Eigen::Index k = columnsOfTangent(xi, "SEK3::ad");
    const Matrix3 P = hat3(xi.template head<3>());
    AdjointMatrix A = AdjointMatrix::Zero(3 + 3 * k, 3 + 3 * k);
    for (Eigen::Index i = 0; i <= k; ++i) A.template block<3, 3>(3 * i, 3 * i) = P;
    for (Eigen::Index i = 0; i < k; ++i) {
      A.template block<3, 3>(3 + 3 * i, 0) = hat3(xi.template segment<3>(3 + 3 * i));
    }
    return A;
  }

  // Jacobians -----------------------------------------------------------------------------
  static Jacobian Jl(const Tangent& xi) {
    const Eigen::Index k = columnsOfTangent(xi, "SEK3::Jl");
    const Vector3 phi = xi.template head<3>();
    const AngleSeries<Scalar> c(phi.squaredNorm());
    const Matrix3 J = SO3Type::Jr(-phi, c);
    const QCoefficients q(c);
    Jacobian out = Jacobian::Zero(3 + 3 * k, 3 + 3 * k);
    for (Eigen::Index i = 0; i <= k; ++i) out.template block<3, 3>(3 * i, 3 * i) = J;
    for (Eigen::Index i = 0; i < k; ++i) {
      out.template block<3, 3>(3 + 3 * i, 0) = Q(phi, xi.template segment<3>(3 + 3 * i), q);
    }
    return out;
  }
  static Jacobian Jr(const Tangent& xi) { return Jl(-xi); }
  static Jacobian JlInv(const Tangent& xi) {
    const Eigen::Index k = columnsOfTangent(xi, "SEK3::JlInv");
    const Vector3 phi = xi.template head<3>();
    const AngleSeries<Scalar> c(phi.squaredNorm());
    const Matrix3 Ji = jlInv(phi, c);
    const QCoefficients q(c);
    Jacobian out = Jacobian::Zero(3 + 3 * k, 3 + 3 * k);
    for (Eigen::Index i = 0; i <= k; ++i) out.template block<3, 3>(3 * i, 3 * i) = Ji;
    for (Eigen::Index i = 0; i < k; ++i) {
      out.template block<3, 3>(3 + 3 * i, 0).noalias() =
          -Ji * Q(phi, xi.template segment<3>(3 + 3 * i), q) * Ji;
    }
    return out;
  }
  static Jacobian JrInv(const Tangent& xi) { return JlInv(-xi); }

  // Plus / minus and interpolation --------------------------------------------------------
  SEK3 rplus(const Tangent& tau) const { return *this * Exp(tau); }
  SEK3 lplus(const Tangent& tau) const { return Exp(tau) * *this; }
  Tangent rminus(const SEK3& X) const { return (X.inverse() * *this).Log(); }  // Log(X^-1 Y)
  Tangent lminus(const SEK3& X) const { return (*this * X.inverse()).Log(); }  // Log(Y X^-1)
  SEK3 interpolate(const SEK3& Y, Scalar t) const { return rplus(t * Y.rminus(*this)); }

  // A uniformly random rotation with columns drawn from N(0, scale^2 I).
  template <typename Generator>
  static SEK3 Random(Generator& gen, Scalar scale = Scalar(1), Eigen::Index k = kDynamic ? 0 : K) {
    std::normal_distribution<Scalar> n01(Scalar(0), Scalar(1));
    Columns C(3, k);
    for (Eigen::Index j = 0; j < k; ++j)
      for (int r = 0; r < 3; ++r) C(r, j) = scale * n01(gen);
    return SEK3(SO3Type::Random(gen), C);
  }

  bool isApprox(const SEK3& Y, Scalar tol = Scalar(1e-10)) const {
    if (numCols() != Y.numCols()) return false;
    const bool rotationClose = (R_ - Y.R_).cwiseAbs().maxCoeff() <= tol;
    if (numCols() == 0) return rotationClose;  // maxCoeff() of an empty matrix is undefined
    const Scalar scale = std::max(Scalar(1), C_.cwiseAbs().maxCoeff());
    return rotationClose && (C_ - Y.C_).cwiseAbs().maxCoeff() <= tol * scale;
  }

  SEK3 normalized() const { return SEK3(rotation().normalized(), C_); }

  // The SE(3) coupling block Q(phi, rho) of the left Jacobian. With a = phi.rho and x = theta^2,
  // the identities [phi][rho][phi] = -a [phi], [phi][rho] + [rho][phi] = phi rho^T + rho phi^T
  // - 2a I and [phi]^2 [rho] + [rho][phi]^2 = -x [rho] - a [phi] turn the file comment's sum of
  // 3x3 products into outer products:
  //   Q = [rho]/2 + G_3 (phi rho^T + rho phi^T - 2a I - a [phi]) + G_4 (2a [phi] - x [rho])
  //       - (G_4 - 3 G_5) a (phi phi^T - x I).
  static Matrix3 Q(const Vector3& phi, const Vector3& rho, const AngleSeries<Scalar>& c) {
    return Q(phi, rho, QCoefficients(c));
  }

  // The angle-only coefficients of Q, evaluated once for all the columns of a Jacobian.
  struct QCoefficients {
    explicit QCoefficients(const AngleSeries<Scalar>& c)
        : x(c.theta2()), g3(c.template G<3>()), g4(c.template G<4>()), g45(c.G45()) {}
    Scalar x, g3, g4, g45;  // theta^2, G_3, G_4, G_4 - 3 G_5
  };
  static Matrix3 Q(const Vector3& phi, const Vector3& rho, const QCoefficients& q) {
    const Scalar a = phi.dot(rho), x = q.x, g3 = q.g3, g4 = q.g4;
    const Scalar k = -q.g45 * a;  // coefficient of phi phi^T - x I
    Matrix3 out = g3 * (phi * rho.transpose() + rho * phi.transpose());
    out += skewSeries(phi, x, -Scalar(2) * g3 * a, Scalar(2) * g4 * a - g3 * a, k);
    out += hat3(Vector3((Scalar(0.5) - g4 * x) * rho));
    return out;
  }

 private:
  struct Unchecked {};
  template <typename RType, typename CType>
  SEK3(const RType& R, const CType& C, Unchecked) : R_(R), C_(C) {}

  static Matrix3 jlInv(const Vector3& phi, const AngleSeries<Scalar>& c) {
    return SO3Type::JlInv(phi, c);
  }

  // The tangent's column part (rho_1..rho_k) viewed as a 3 x k matrix.
  static auto rhoOf(const Tangent& xi, Eigen::Index k) {
    return Eigen::Map<const Eigen::Matrix<Scalar, 3, K>>(xi.data() + 3, 3, k);
  }
  static auto rhoOf(Tangent& xi, Eigen::Index k) {
    return Eigen::Map<Eigen::Matrix<Scalar, 3, K>>(xi.data() + 3, 3, k);
  }

  static void checkColumnCount(Eigen::Index k, const char* where) {
    if (k < 0 || k > MaxK || (!kDynamic && k != K)) throwColumnCount(k, where);
  }
  [[noreturn]] __attribute__((noinline, cold)) static void throwColumnCount(Eigen::Index k,
                                                                            const char* where) {
    std::ostringstream os;
    os << where << ": " << k << " columns requested, this group holds "
       << (kDynamic ? "at most " : "exactly ") << MaxK;
    throw std::invalid_argument(os.str());
  }
  static Eigen::Index columnsOfTangent(const Tangent& xi, const char* where) {
    const Eigen::Index n = xi.size();
    if ((n - 3) % 3 != 0 || n < 3) {
      std::ostringstream os;
      os << where << ": tangent vector of size " << n << " is not 3 + 3K";
      throw std::invalid_argument(os.str());
    }
    checkColumnCount((n - 3) / 3, where);
    return (n - 3) / 3;
  }
  void checkSameK(const SEK3& Y, const char* where) const {
    if (kDynamic && Y.numCols() != numCols()) {
      std::ostringstream os;
      os << where << ": operands have " << numCols() << " and " << Y.numCols() << " columns";
      throw std::invalid_argument(os.str());
    }
  }

  Matrix3 R_;
  Columns C_;
};

template <typename Scalar>
using SE3 = SEK3<Scalar, 1>;
template <typename Scalar>
using SE23 = SEK3<Scalar, 2>;
// SE_K(3) whose number of columns changes at run time, up to MaxK, without heap allocation.
template <typename Scalar, int MaxK>
using SEKd = SEK3<Scalar, Eigen::Dynamic, MaxK>;

using SE3d = SE3<double>;
using SE23d = SE23<double>;

}  // namespace lie
