# (owner: lieauto)
# lie/ generic in its scalar: the autodiff derivatives (ceres::Jet, Eigen::AutoDiffScalar) of
# Exp, Log, act, compose and inverse against the closed-form Jacobians. Ceres only for its Jet
# type here; the lie/ headers themselves stay Eigen-only.
find_package(Ceres 2.1 REQUIRED)
legkit_add_test(test_lie_autodiff SOURCES autodiff_test.cpp LIBS lie::lie Ceres::ceres LABELS "lie")
