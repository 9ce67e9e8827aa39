// eigen_sym3 (own cyclic Jacobi) against Eigen's SelfAdjointEigenSolver in double,
// degenerate inputs, and PCA of point sets whose covariance is known in closed form.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

#include "fg/core/eigen_sym3.hpp"

namespace {

using fg::Mat3;
using fg::Vec3;

// Checks of one decomposition that need no oracle: ascending, orthonormal,
// right-handed, A v = lambda v.
void expect_valid_decomposition(const Mat3& A, const Vec3& evals, const Mat3& V, double tol_rel) {
  const Eigen::Matrix3d Ad = A.cast<double>();
  const Eigen::Matrix3d Vd = V.cast<double>();
  const double norm = std::max(Ad.norm(), std::numeric_limits<double>::min());
  EXPECT_LE(evals(0), evals(1));
  EXPECT_LE(evals(1), evals(2));
  EXPECT_NEAR((Vd.transpose() * Vd - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-6);
  EXPECT_NEAR(Vd.determinant(), 1.0, 1e-6);
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector3d r = Ad * Vd.col(c) - static_cast<double>(evals(c)) * Vd.col(c);
    EXPECT_LE(r.norm(), tol_rel * norm) << "column " << c;
  }
}

Mat3 random_symmetric(std::mt19937& rng, float scale) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Mat3 A;
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      A(i, j) = scale * u(rng);
      A(j, i) = A(i, j);
    }
  }
  return A;
}

void compare_with_eigen(const Mat3& A) {
  Vec3 evals;
  Mat3 V;
  ASSERT_TRUE(fg::eigen_sym3(A, evals, V));
  const Eigen::Matrix3d Ad = A.cast<double>();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ref(Ad);  // ascending eigenvalues
  ASSERT_EQ(ref.info(), Eigen::Success);
  const double norm = Ad.norm();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(evals(i), ref.eigenvalues()(i), 1e-5 * norm) << A;
  }
  for (int i = 0; i < 3; ++i) {
    double gap = std::numeric_limits<double>::infinity();
    for (int j = 0; j < 3; ++j) {
      if (j != i) gap = std::min(gap, std::fabs(ref.eigenvalues()(i) - ref.eigenvalues()(j)));
    }
    if (gap > 1e-3 * norm) {
      const double dot = std::fabs(V.col(i).cast<double>().dot(ref.eigenvectors().col(i)));
      EXPECT_GT(dot, 1.0 - 1e-4) << "column " << i << "\n" << A;
    }
  }
  expect_valid_decomposition(A, evals, V, 1e-5);
}

}  // namespace

TEST(EigenSym3, MatchesEigenOnRandomSymmetricMatrices) {
  std::mt19937 rng(20240611u);
  std::uniform_real_distribution<float> log_scale(-3.0f, 3.0f);
  for (int t = 0; t < 10000; ++t) {
    const Mat3 A = random_symmetric(rng, std::pow(10.0f, log_scale(rng)));
    compare_with_eigen(A);
    if (HasFailure()) {
      ADD_FAILURE() << "stopped at trial " << t;
      return;
    }
  }
}

TEST(EigenSym3, MatchesEigenOnRotatedDiagonalsWithCloseEigenvalues) {
  // R diag(d) R^T with two eigenvalues 1e-6 apart and with a spread of 1e6.
  std::mt19937 rng(7u);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double diags[4][3] = {{1.0, 1.0 + 1e-6, 3.0}, {1e-6, 1.0, 1e6}, {-5.0, 0.0, 5.0}, {-2.0, -2.0, 7.0}};
  for (int t = 0; t < 200; ++t) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    const Eigen::Matrix3d R = q.toRotationMatrix();
    const double* d = diags[t % 4];
    const Eigen::Matrix3d Ad = R * Eigen::Vector3d(d[0], d[1], d[2]).asDiagonal() * R.transpose();
    compare_with_eigen(Ad.cast<float>());
  }
}

TEST(EigenSym3, ReadsOnlyTheUpperTriangle) {
  Mat3 A;
  A << 2.0f, 1.0f, 0.5f, std::numeric_limits<float>::quiet_NaN(), 3.0f, -1.0f, 1e30f,
      std::numeric_limits<float>::infinity(), 4.0f;
  Vec3 evals;
  Mat3 V;
  ASSERT_TRUE(fg::eigen_sym3(A, evals, V));
  Mat3 S = A;
  S(1, 0) = S(0, 1);
  S(2, 0) = S(0, 2);
  S(2, 1) = S(1, 2);
  compare_with_eigen(S);
  Vec3 evals_s;
  Mat3 V_s;
  ASSERT_TRUE(fg::eigen_sym3(S, evals_s, V_s));
  EXPECT_EQ(evals, evals_s);
  EXPECT_EQ(V, V_s);
}

TEST(EigenSym3, IdentityAndRepeatedEigenvalues) {
  Vec3 evals;
  Mat3 V;
  ASSERT_TRUE(fg::eigen_sym3(Mat3::Identity(), evals, V));
  EXPECT_EQ(evals, Vec3(1.0f, 1.0f, 1.0f));
  EXPECT_EQ(V, Mat3::Identity());

  Mat3 D = Mat3::Zero();
  D.diagonal() << 2.0f, 1.0f, 1.0f;  // diag(1, 1, 2) in another order
  ASSERT_TRUE(fg::eigen_sym3(D, evals, V));
  EXPECT_FLOAT_EQ(evals(0), 1.0f);
  EXPECT_FLOAT_EQ(evals(1), 1.0f);
  EXPECT_FLOAT_EQ(evals(2), 2.0f);
  EXPECT_NEAR(std::fabs(V(0, 2)), 1.0f, 1e-6f);  // the simple eigenvalue's vector is e_x
  expect_valid_decomposition(D, evals, V, 1e-6);

  // A rotated diag(1, 1, 2): the repeated eigenspace is the plane normal to the axis.
  const Eigen::Matrix3f R = Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1.0f, 2.0f, -0.5f).normalized()).toRotationMatrix();
  const Mat3 A = R * Eigen::Vector3f(1.0f, 1.0f, 2.0f).asDiagonal() * R.transpose();
  ASSERT_TRUE(fg::eigen_sym3(A, evals, V));
  EXPECT_NEAR(evals(0), 1.0f, 1e-5f);
  EXPECT_NEAR(evals(1), 1.0f, 1e-5f);
  EXPECT_NEAR(evals(2), 2.0f, 1e-5f);
  EXPECT_GT(std::fabs(V.col(2).dot(R.col(2))), 1.0f - 1e-5f);
  EXPECT_LT(std::fabs(V.col(0).dot(R.col(2))), 1e-3f);
  EXPECT_LT(std::fabs(V.col(1).dot(R.col(2))), 1e-3f);
  expect_valid_decomposition(A, evals, V, 1e-5);

  // Three equal eigenvalues off the identity: 5 I.
  ASSERT_TRUE(fg::eigen_sym3(5.0f * Mat3::Identity(), evals, V));
  EXPECT_EQ(evals, Vec3(5.0f, 5.0f, 5.0f));
  EXPECT_NEAR(V.determinant(), 1.0f, 1e-6f);
}

TEST(EigenSym3, ZeroMatrix) {
  Vec3 evals(1.0f, 2.0f, 3.0f);
  Mat3 V = Mat3::Zero();
  ASSERT_TRUE(fg::eigen_sym3(Mat3::Zero(), evals, V));
  EXPECT_EQ(evals, Vec3::Zero());
  EXPECT_EQ(V, Mat3::Identity());
}

TEST(EigenSym3, HugeAndTinyScales) {
  std::mt19937 rng(99u);
  const float scales[] = {1e30f, 1e20f, 1e-20f, 1e-30f, 1e-36f};
  for (float s : scales) {
    for (int t = 0; t < 200; ++t) {
      const Mat3 A = random_symmetric(rng, s);
      Vec3 evals;
      Mat3 V;
      ASSERT_TRUE(fg::eigen_sym3(A, evals, V)) << s;
      const Eigen::Matrix3d Ad = A.cast<double>();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ref(Ad);
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(evals(i), ref.eigenvalues()(i), 1e-5 * Ad.norm()) << s;
      }
      expect_valid_decomposition(A, evals, V, 1e-5);
    }
  }
  // Denormal entries.
  Mat3 A = Mat3::Zero();
  A(0, 0) = 1e-44f;
  A(1, 1) = 3e-45f;
  Vec3 evals;
  Mat3 V;
  ASSERT_TRUE(fg::eigen_sym3(A, evals, V));
  EXPECT_EQ(evals(0), 0.0f);
  EXPECT_EQ(evals(1), 3e-45f);
  EXPECT_EQ(evals(2), 1e-44f);
}

TEST(EigenSym3, EigenvaluesBeyondTheFloatRangeFail) {
  const Mat3 A = Mat3::Constant(3e38f);  // largest eigenvalue 9e38 > FLT_MAX
  Vec3 evals;
  Mat3 V;
  EXPECT_FALSE(fg::eigen_sym3(A, evals, V));
  EXPECT_EQ(evals, Vec3::Zero());
  EXPECT_EQ(V, Mat3::Identity());
}

TEST(EigenSym3, NonFiniteInputFails) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
  const int upper[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  for (float b : bad) {
    for (const auto& ij : upper) {
      Mat3 A = Mat3::Identity();
      A(ij[0], ij[1]) = b;
      A(ij[1], ij[0]) = b;
      Vec3 evals(1.0f, 2.0f, 3.0f);
      Mat3 V = Mat3::Zero();
      EXPECT_FALSE(fg::eigen_sym3(A, evals, V));
      EXPECT_EQ(evals, Vec3::Zero());
      EXPECT_EQ(V, Mat3::Identity());
    }
  }
}

TEST(EigenSym3, Deterministic) {
  std::mt19937 rng(5u);
  for (int t = 0; t < 100; ++t) {
    const Mat3 A = random_symmetric(rng, 1.0f);
    Vec3 e1, e2;
    Mat3 V1, V2;
    ASSERT_TRUE(fg::eigen_sym3(A, e1, V1));
    ASSERT_TRUE(fg::eigen_sym3(A, e2, V2));
    EXPECT_EQ(e1, e2);
    EXPECT_EQ(V1, V2);
  }
}

// ---------------------------------------------------------------------------------
// PCA

TEST(Pca, PointsOnALine) {
  const Vec3 origin(0.3f, -1.2f, 0.8f);
  const Vec3 dir = Vec3(1.0f, 2.0f, 2.0f) / 3.0f;
  Vec3 pts[101];
  double var = 0.0;
  for (int i = 0; i <= 100; ++i) {
    const float s = 0.002f * static_cast<float>(i - 50);  // -0.1 .. 0.1 m
    pts[i] = origin + s * dir;
    var += static_cast<double>(s) * s;
  }
  var /= 101.0;
  Vec3 c, evals;
  Mat3 V;
  ASSERT_TRUE(fg::pca(pts, 101, c, evals, V));
  EXPECT_NEAR((c - origin).norm(), 0.0f, 1e-6f);
  EXPECT_NEAR(evals(2), var, 1e-6 * var + 1e-9);
  EXPECT_NEAR(evals(0), 0.0f, 1e-9f);
  EXPECT_NEAR(evals(1), 0.0f, 1e-9f);
  EXPECT_GE(evals(0), 0.0f);
  EXPECT_GT(std::fabs(V.col(2).dot(dir)), 1.0f - 1e-5f);
  EXPECT_NEAR(V.determinant(), 1.0f, 1e-5f);
}

TEST(Pca, PointsOnAPlane) {
  // A 21 x 11 grid, 4 mm spacing, in a tilted plane far from the origin.
  const Eigen::Matrix3f R = Eigen::AngleAxisf(0.9f, Eigen::Vector3f(0.3f, -1.0f, 0.4f).normalized()).toRotationMatrix();
  const Vec3 origin(100.0f, -50.0f, 20.0f);
  Vec3 pts[21 * 11];
  uint32_t n = 0;
  for (int i = -10; i <= 10; ++i) {
    for (int j = -5; j <= 5; ++j) {
      pts[n++] = origin + R * Vec3(0.004f * static_cast<float>(i), 0.004f * static_cast<float>(j), 0.0f);
    }
  }
  Vec3 c, evals;
  Mat3 V;
  ASSERT_TRUE(fg::pca(pts, n, c, evals, V));
  EXPECT_NEAR((c - origin).norm(), 0.0f, 2e-5f);
  // Var of 0.004 * {-10..10} = 0.004^2 * 110 / 3; of 0.004 * {-5..5} = 0.004^2 * 10.
  EXPECT_NEAR(evals(2), 0.004 * 0.004 * 110.0 / 3.0, 1e-3 * 0.004 * 0.004 * 110.0 / 3.0);
  EXPECT_NEAR(evals(1), 0.004 * 0.004 * 10.0, 1e-3 * 0.004 * 0.004 * 10.0);
  EXPECT_LT(evals(0), 1e-9f);
  EXPECT_GT(std::fabs(V.col(0).dot(R.col(2))), 1.0f - 1e-4f);  // the normal
  EXPECT_GT(std::fabs(V.col(2).dot(R.col(0))), 1.0f - 1e-4f);
}

TEST(Pca, SymmetricPointSetHasItsClosedFormCovariance) {
  // +-a e1, +-b e2, +-c e3 in a rotated frame: covariance R diag(a^2, b^2, c^2)/3 R^T.
  const Eigen::Matrix3f R = Eigen::AngleAxisf(-1.3f, Eigen::Vector3f(2.0f, 1.0f, 0.5f).normalized()).toRotationMatrix();
  const Vec3 centre(0.5f, 0.25f, -0.75f);
  const float a = 0.3f, b = 0.2f, cc = 0.05f;
  const Vec3 pts[6] = {centre + a * R.col(0), centre - a * R.col(0),  centre + b * R.col(1),
                       centre - b * R.col(1), centre + cc * R.col(2), centre - cc * R.col(2)};
  Vec3 c, evals;
  Mat3 V;
  ASSERT_TRUE(fg::pca(pts, 6, c, evals, V));
  EXPECT_NEAR((c - centre).norm(), 0.0f, 1e-6f);
  EXPECT_NEAR(evals(0), cc * cc / 3.0f, 1e-6f);
  EXPECT_NEAR(evals(1), b * b / 3.0f, 1e-6f);
  EXPECT_NEAR(evals(2), a * a / 3.0f, 1e-6f);
  EXPECT_GT(std::fabs(V.col(0).dot(R.col(2))), 1.0f - 1e-5f);
  EXPECT_GT(std::fabs(V.col(1).dot(R.col(1))), 1.0f - 1e-5f);
  EXPECT_GT(std::fabs(V.col(2).dot(R.col(0))), 1.0f - 1e-5f);
  EXPECT_NEAR(V.determinant(), 1.0f, 1e-5f);
}

TEST(Pca, RandomEllipsoidMatchesADoubleTwoPassOracle) {
  std::mt19937 rng(314u);
  std::normal_distribution<float> nd(0.0f, 1.0f);
  const Eigen::Matrix3f R = Eigen::AngleAxisf(0.4f, Eigen::Vector3f(-1.0f, 0.2f, 0.9f).normalized()).toRotationMatrix();
  const Vec3 sigma(0.10f, 0.03f, 0.01f);
  const Vec3 offset(2.0f, -3.0f, 1.0f);
  static Vec3 pts[5000];
  for (auto& p : pts) p = offset + R * Vec3(sigma(0) * nd(rng), sigma(1) * nd(rng), sigma(2) * nd(rng));
  Vec3 c, evals;
  Mat3 V;
  ASSERT_TRUE(fg::pca(pts, 5000, c, evals, V));
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p.cast<double>();
  mean /= 5000.0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) {
    const Eigen::Vector3d d = p.cast<double>() - mean;
    cov += d * d.transpose();
  }
  cov /= 5000.0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ref(cov);
  EXPECT_NEAR((c.cast<double>() - mean).norm(), 0.0, 1e-6);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(evals(i), ref.eigenvalues()(i), 1e-5 * ref.eigenvalues()(2));
    EXPECT_GT(std::fabs(V.col(i).cast<double>().dot(ref.eigenvectors().col(i))), 1.0 - 1e-4);
  }
  // And the sampled axes are the generating ones.
  EXPECT_GT(std::fabs(V.col(2).dot(R.col(0))), 0.999f);
  EXPECT_GT(std::fabs(V.col(0).dot(R.col(2))), 0.999f);
}

TEST(Pca, DegenerateInputs) {
  Vec3 c, evals;
  Mat3 V;
  EXPECT_FALSE(fg::pca(nullptr, 0, c, evals, V));
  const Vec3 one(1.0f, 2.0f, 3.0f);
  EXPECT_FALSE(fg::pca(&one, 0, c, evals, V));
  EXPECT_EQ(evals, Vec3::Zero());
  EXPECT_EQ(V, Mat3::Identity());

  ASSERT_TRUE(fg::pca(&one, 1, c, evals, V));  // a single point: zero covariance
  EXPECT_EQ(c, one);
  EXPECT_EQ(evals, Vec3::Zero());
  EXPECT_EQ(V, Mat3::Identity());

  Vec3 pts[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  pts[2].y() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(fg::pca(pts, 4, c, evals, V));
  EXPECT_EQ(evals, Vec3::Zero());
  EXPECT_EQ(V, Mat3::Identity());
  pts[2].y() = 1.0f;
  pts[0].x() = std::numeric_limits<float>::infinity();  // the shift point itself
  EXPECT_FALSE(fg::pca(pts, 4, c, evals, V));
}
