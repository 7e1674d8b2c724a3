#pragma once
// The material of a stroke thrombus: its stiffness in compression and its friction on the
// arterial wall, from its composition (sources in clot_material.cpp and sim/flow/README.md).
//
// - Composition: histological area fractions (%) of red cells and of fibrin/platelets
//   (leukocytes the rest), as a thrombectomy specimen is graded.
// - Stiffness: the tangent modulus at 75 % strain in unconfined compression, Et75 = 560 kPa
//   at the reference composition, +9 kPa per % fibrin/platelets and -9 kPa per % red cells
//   (Boodt et al., Stroke 2021, multivariable model), floored at 10 % of the median.
// - Compression: strain-stiffening, nominal stress sigma(e) = A (exp(B e) - 1), with B such
//   that the tangent at 75 % strain is ~600 times the tangent at small strain (Cahalane et al.,
//   Ann Biomed Eng 2023: high-strain compressive stiffness ~40 x the tensile stiffness, which
//   is ~15 x the low-strain compressive stiffness) and A such that the tangent at 75 % strain
//   is Et75.
// - Wall friction: static and kinetic coefficients interpolated over the clot's equivalent
//   analogue haematocrit (Elkhayyat et al., J Biomech 2024: static 1.49 / 0.57 / 0.46 at 0 / 20
//   / 40 % haematocrit, kinetic 0.26 / 0.23 at 20 / 40 %).
namespace cathbox::flow {

struct ClotComposition {
  double red_cell_percent = 45.0;
  double fibrin_platelet_percent = 45.0;
  friend bool operator==(const ClotComposition&, const ClotComposition&) = default;
};

// The composition the 560 kPa median refers to in this model: balanced red cells and
// fibrin/platelets, 10 % leukocytes.
inline constexpr ClotComposition kReferenceComposition{45.0, 45.0};
inline constexpr double kMedianEt75_kPa = 560.0;     // Boodt et al. 2021, IQR 393-1161
inline constexpr double kEt75PerPercent_kPa = 9.0;   // Boodt et al. 2021, 95 % CI 5-13
inline constexpr double kStrainStiffeningRatio = 600.0;  // Cahalane et al. 2023: 40 x 15

// Empty when valid, else one line naming the bad value (percentages in [0, 100], sum <= 100).
[[nodiscard]] const char* check_composition(const ClotComposition& c);

// Tangent modulus at 75 % strain, kPa.
[[nodiscard]] double clot_et75_kPa(const ClotComposition& c);

// The strain-stiffening compression law of one composition.
class ClotCompressionLaw {
 public:
  explicit ClotCompressionLaw(const ClotComposition& c);
  // Nominal (engineering) compressive stress at a compressive strain in [0, 0.95], kPa.
  [[nodiscard]] double stress_kPa(double strain) const;
  // Tangent modulus d(stress)/d(strain), kPa.
  [[nodiscard]] double tangent_kPa(double strain) const;
  // Force, N, to compress a clot of cross-section area `area_mm2` (unloaded) by `strain`.
  [[nodiscard]] double force_N(double strain, double area_mm2) const;
  [[nodiscard]] double et75_kPa() const { return et75_kPa_; }

 private:
  double et75_kPa_;
  double a_kPa_;
  double b_;
};

struct ClotFriction {
  double static_coefficient = 0.0;
  double kinetic_coefficient = 0.0;
};

// The haematocrit (%) of the blood a clot analogue of this composition is made from: 0 % for a
// pure fibrin clot, 20 % at 45 % red cells, 40 % at 80 % red cells and above (a modelling
// mapping of histology onto the analogues of the friction study).
[[nodiscard]] double equivalent_haematocrit_percent(const ClotComposition& c);
[[nodiscard]] ClotFriction clot_wall_friction(const ClotComposition& c);

}  // namespace cathbox::flow
