#pragma once
// The haemostatic valve a tool slides through (the introducer sheath's for a tool in the
// vessel, the Y-connector on the catheter's hub for a coaxial one): Coulomb friction felt at
// the hand as a roughly constant force against the motion, whatever the tool does inside. Like
// the wall and lumen friction it is an elastic-plastic anchor: sticking, the hand feels the
// anchor's stiffness up to the limit; slipping, the limit. The twist sees the same friction at
// the tool's surface: a torque limit of F r with a stiffness of k r^2.
namespace cathbox::tool {

class ValveFriction {
 public:
  struct Result {
    double force_mN = 0.0;     // positive resists insertion
    double torque_mNmm = 0.0;  // positive resists rotation
    bool sticking = false;
    bool twist_sticking = false;
  };
  // position_mm / angle_rad: where the tool is through the valve; engaged: the tool is in it.
  Result update(double position_mm, double angle_rad, bool engaged, double limit_mN, double radius_mm,
                double anchor_stiffness_mN_per_mm);

 private:
  double anchor_mm_ = 0.0;
  double anchor_rad_ = 0.0;
};

}  // namespace cathbox::tool
