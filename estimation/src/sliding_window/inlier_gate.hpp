#pragma once
// Private to the sliding-window estimator: the inlier gate that the covariance and the
// marginalization prior evaluate the visual factors with (covariance_weights / prior_weights:
// inliers; docs/estimator.md, "Covariance" and "Marginalization").
#include <ceres/loss_function.h>

#include "impl.hpp"

namespace navaid::estimation::sliding_window {

// rho(s) = s up to the gate, constant beyond it: full Gaussian weight for inliers, none for outliers.
class InlierGate final : public ceres::LossFunction {
 public:
  void Evaluate(double s, double rho[3]) const override {
    const bool inlier = s <= kCovarianceGate;
    rho[0] = inlier ? s : kCovarianceGate;
    rho[1] = inlier ? 1.0 : 0.0;
    rho[2] = 0.0;
  }
};

// Puts the inlier gate (or, `gaussian`, no loss at all) into the visual factors' loss wrapper for
// its lifetime (no-op when disabled or without a robust loss).
class GatedLoss {
 public:
  GatedLoss(ceres::LossFunctionWrapper* wrapper, ceres::LossFunction* robust, bool enabled, bool gaussian = false)
      : wrapper_(enabled ? wrapper : nullptr), robust_(robust) {
    if (wrapper_) wrapper_->Reset(gaussian ? nullptr : &gate_, ceres::DO_NOT_TAKE_OWNERSHIP);
  }
  ~GatedLoss() {
    if (wrapper_) wrapper_->Reset(robust_, ceres::DO_NOT_TAKE_OWNERSHIP);
  }
  GatedLoss(const GatedLoss&) = delete;
  GatedLoss& operator=(const GatedLoss&) = delete;

 private:
  InlierGate gate_;
  ceres::LossFunctionWrapper* wrapper_;
  ceres::LossFunction* robust_;
};

}  // namespace navaid::estimation::sliding_window
