#pragma once
// Training the factor model (Drew & Finlayson; Bergner et al. 2009 §2.2–2.3, design.md §4):
// uncentred PCA of colour signals, interval sharpening, then refinement of the sharpening
// transform T (and of the interval borders) against the product error on the training set,
// single products *and* deep-absorption products, with the coefficients kept bounded.
// Refinement is what makes the model stable: closed-form sharpening alone can put a white
// coefficient near zero and blow every coefficient up.

#include <memory>
#include <string>
#include <vector>

#include "spectral/colorimetry.h"
#include "spectral/componentwise_model.h"
#include "spectral/linear_model.h"

namespace svr {

struct TrainingSet {
  std::vector<Spectrum> lights;        // each at unit luminance (Observer::unitLuminance)
  std::vector<Spectrum> reflectances;  // colour signals are every light × every reflectance
  // Per-step transmittances, paired with reflectances (same count): the deep products are
  // light × reflectance[j] × absorber[j]^m for every m in depths.
  std::vector<Spectrum> absorbers;
  std::vector<int> depths{16, 64, 256};
};

// A deep product counts in training and in trainingSetError only where the light comes through
// t^m visibly: its Y at least this, the unfiltered light's being 1 (L* ≈ 1). Below it the image
// is black whatever the model does, and an exposure-normalised fit to it would spend the
// model's channels on colours nobody sees.
constexpr double kVisibleDepthY = 1e-3;

// How far a model's colours rest on cancellation: the largest, over X, Y and Z, of
// Σ_j |toXyz_ij| against |Σ_j toXyz_ij| (the white, whose coefficients are all 1). Renderers
// accumulate coefficients in float32 (relative rounding 6e-8), so a model that cancels by 1e7
// fits its palette in double and paints noise: found on issue 40's corpus, a factor:5 with toXyz
// entries of 8e8 whose palette error was 0.04 and whose image was 27 from spectral:81. Trained
// models stay below kMaxCancellation. At 10³ a phantom factor:6/projected (cancellation 799,
// toXyz columns of ±4.3e4) broke relit = baked-in light by 1.006× the test's float tolerance;
// the models the scenes and tests trained before measured 1–600, most below 50.
constexpr double kMaxCancellation = 100;
double toXyzCancellation(const XyzMatrix& to_xyz);

// The mean ΔE2000 over what training fits: every light × reflectance, and every visible deep
// product light × reflectance × absorber^m (exposure-normalised, ColourModel's clamped
// transmittance coefficients), Lab against each light's white. Infinite when not finite or
// when the model cancels by more than kMaxCancellation.
double trainingSetError(const ColourModel& model, const Observer& observer,
                        const TrainingSet& set);

// The same model with one channel more: its last channel split into two equal halves (the
// projection's row repeated, the basis column and toXyz's column halved), so every product and
// every relit colour is the same. A k-channel candidate that is never worse than k − 1's.
std::unique_ptr<ComponentwiseModel> withChannelSplit(const ComponentwiseModel& model);

// rgb as a factor:k candidate (k ≥ 3): rgb's projection with its last channel split k − 3
// times, relit with projected light matrices, so every relit colour is rgb's. factor:k then
// never has to lose to rgb.
std::unique_ptr<ComponentwiseModel> rgbFactorModel(const Observer& observer, int k);

// k equal bands of the grid (spectral:k's band means) as a factor:k candidate: its projection is
// non-negative, so coefficients of a transmittance stay in [0, 1] without clamping and deep
// products stay exact in every band's mean. Stable under any absorption, if coarse.
std::unique_ptr<ComponentwiseModel> bandFactorModel(const Observer& observer, int k,
                                                    LightMatrixKind light_matrix);

// The deep-absorption absorber of design.md §4: t = 0.97 + 0.03·r, with r a different chip.
Spectrum weakAbsorber(const Spectrum& reflectance);
// For each j, a partner index != j drawn with the given seed (a fixed, portable generator).
std::vector<int> partnerIndices(int count, unsigned seed);
// Deterministic permutation of 0..count-1 (Fisher–Yates over std::mt19937).
std::vector<int> shuffledIndices(int count, unsigned seed);

enum class FactorVariant {
  kPca,      // unsharpened PCA basis: the contrast every sharpened variant must beat
  kSharp,    // closed-form equal-interval sharpening, white-normalised (known unstable)
  kRefined,  // the product model: border search + Levenberg–Marquardt on single and deep products
};
std::string toString(FactorVariant v);

struct FactorTrainingReport {
  std::string start;             // starting sharpening the refinement began from
  double objective_start = 0.0;  // training cost (ProductObjective::cost)
  double objective_final = 0.0;
  int iterations = 0;
  std::vector<double> borders_nm;  // interval borders of the sharpening start
  double white_min_abs = 0.0;      // smallest |white coefficient| before normalisation
};

// n×k orthonormal basis: the first k left singular vectors of the colour signals.
Eigen::MatrixXd principalBasis(const TrainingSet& set, int k);

// The starting span of a model for full-spectrum light matrices (colour_model.h): there the
// light never enters a componentwise product, so the basis has to hold what the image holds —
// reflectances and their products with the absorbers (R ⊙ t^m, exposure-normalised) — as the
// training lights see them: the principal components in the metric
//   M = Σ_l diag(L_l) C Cᵀ diag(L_l) + ε·tr(M)/n·I     (C: weighted CMFs, n×3),
// the XYZ error of a reconstruction under every light, ε = 1e-2 keeping the invisible rest of
// the spectrum from being arbitrary. Returns an orthonormal n×k `basis` and the k×n
// M-weighted `projection` onto it (projection · basis = I).
struct StartingSpan {
  Eigen::MatrixXd basis, projection;
};
StartingSpan lightWeightedSpan(const Observer& observer, const TrainingSet& set, int k);

// previous_basis (n × (k−1)), the basis of the same set's model with one channel fewer, adds a
// nested start: that model plus one new channel.
// light_matrix: what the model relights with, and so what training fits. Projected: the basis
// spans the colour signals (light × reflectance) and products with the light's coefficients
// are fitted; full: the basis spans lightWeightedSpan and products of reflectance and absorbers
// are fitted with the light applied as a full spectrum.
std::unique_ptr<ComponentwiseModel> trainFactorModel(const Observer& observer,
                                                     const TrainingSet& set, int k,
                                                     FactorVariant variant,
                                                     LightMatrixKind light_matrix,
                                                     FactorTrainingReport* report = nullptr,
                                                     const Eigen::MatrixXd* previous_basis = nullptr);
std::unique_ptr<LinearModel> trainLinearModel(const Observer& observer, const TrainingSet& set,
                                              int k);

}  // namespace svr
