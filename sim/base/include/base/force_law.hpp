#pragma once
// The local force law the box renders between simulation updates, linearised around the
// present state of the active tool:
//   force_mN  = force0_mN  + stiffness_mN_per_mm      * (insertion_mm - insertion0_mm) + damping_mN_s_per_mm * v_mm_s
//   torque_mNmm = torque0_mNmm + torsion_stiffness_mNmm_per_rad * (rotation_rad - rotation0_rad) + torsion_damping * w_rad_s
// Force and torque are what the tool exerts on the hand: positive resists insertion / rotation.
// A vocabulary type: the tool solver produces it, the session maps it to the box's frame and
// the device driver turns it into a command report, without the driver knowing the simulator.
namespace cathbox::base {

struct ForceLaw {
  double insertion0_mm = 0.0;
  double force0_mN = 0.0;
  double stiffness_mN_per_mm = 0.0;
  double damping_mN_s_per_mm = 0.0;
  double rotation0_rad = 0.0;
  double torque0_mNmm = 0.0;
  double torsion_stiffness_mNmm_per_rad = 0.0;
  double torsion_damping_mNmm_s_per_rad = 0.0;

  [[nodiscard]] double force_mN(double insertion_mm, double speed_mm_s) const {
    return force0_mN + stiffness_mN_per_mm * (insertion_mm - insertion0_mm) + damping_mN_s_per_mm * speed_mm_s;
  }
  [[nodiscard]] double torque_mNmm(double rotation_rad, double speed_rad_s) const {
    return torque0_mNmm + torsion_stiffness_mNmm_per_rad * (rotation_rad - rotation0_rad) +
           torsion_damping_mNmm_s_per_rad * speed_rad_s;
  }
};

}  // namespace cathbox::base
