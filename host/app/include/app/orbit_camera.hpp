#pragma once
// The global view's camera: orbits a target point (yaw about +Z, pitch above the XY plane),
// zooms by changing the distance, pans by moving the target in the view plane.
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace cathbox::app {

class OrbitCamera {
 public:
  // Looks at the centre of the box from the front (-Y), far enough to see all of it.
  void frame(const glm::vec3& min_mm, const glm::vec3& max_mm);

  void orbit(float dx_px, float dy_px);
  void zoom(float steps);  // positive: closer
  void pan(float dx_px, float dy_px, float viewport_height_px);

  [[nodiscard]] glm::vec3 eye_mm() const;
  [[nodiscard]] glm::mat4 view() const;
  [[nodiscard]] glm::mat4 projection(float aspect) const;
  // The ray from the eye through a pixel of a view of the given size (origin at its top left):
  // for picking. Returns the unit direction; the origin is eye_mm().
  [[nodiscard]] glm::vec3 ray_through(float x_px, float y_px, float width_px, float height_px) const;

  glm::vec3 target_mm{0.0F};
  float distance_mm = 100.0F;
  float yaw_rad = -1.5707963F;
  float pitch_rad = 0.0F;
  float fov_y_rad = 0.7853982F;
  float scene_radius_mm = 50.0F;
};

// The local view: from just ahead of the tool tip (clear of the tool's own surface), looking
// along the tip direction.
struct EndoCamera {
  [[nodiscard]] static glm::mat4 view(const glm::vec3& tip_mm, const glm::vec3& direction,
                                      const glm::vec3& up_hint, float ahead_mm = 0.6F);
  [[nodiscard]] static glm::mat4 projection(float aspect);
};

}  // namespace cathbox::app
