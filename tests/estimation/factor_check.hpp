#pragma once
// Test helpers of the estimation suite: analytic-vs-numeric Jacobians on the parameter manifolds,
// random states, and the pose manifold for every 7-double block.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/manifold.h>

#include "navaid/core/geometry.hpp"

namespace navaid::estimation::testing {

/// Compares the cost function's Jacobians, mapped to each block's tangent space
/// (J_ambient * PlusJacobian), with central differences of the residual along Plus(x, +-h e_k).
/// A null manifold means Euclidean. Passes when max |J_analytic - J_numeric| <= tol * max(1, max |J|)
/// per block.
::testing::AssertionResult jacobians_match(const ceres::CostFunction& f, const std::vector<double*>& blocks,
                                           const std::vector<const ceres::Manifold*>& manifolds, double tol = 1e-7,
                                           double step = 1e-5);

/// A random rotation (uniform axis, angle up to max_angle).
Quat random_rotation(std::mt19937_64& rng, double max_angle = 3.0);
Vec3 random_vector(std::mt19937_64& rng, double scale);
SE3 random_pose(std::mt19937_64& rng, double translation_scale = 2.0);

}  // namespace navaid::estimation::testing
