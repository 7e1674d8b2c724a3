#pragma once

// The fluoroscopy renderer's GLSL sources, one text for two dialects: the native FluoroRenderer
// (fluoro_renderer.cpp, GLSL 3.30 core) and the trainee page's WebGL2 view (js/fluoro_view.js,
// GLSL ES 3.00), which gets them from the WebAssembly session (cbx_fluoro_shader, host/wasm).
// Each text starts without its #version line: the caller puts kDesktopVersion or kEsVersion
// first, then its #defines (the composite's MODE, SCENE, FBFETCH). GL_ES, which every GLSL ES
// compiler defines, selects what WebGL2 lacks: buffer textures (the cells' iodine is a 2D float
// texture there) and framebuffer fetch.

namespace cathbox::app::fluoro_glsl {

inline constexpr const char* kDesktopVersion = "#version 330 core\n";
inline constexpr const char* kEsVersion = "#version 300 es\n";

// Scene pass: every face of a closed mesh adds sign * mu * d (d: distance from the source less
// the isocentre's), entering (front) faces negative, so a ray sums mu times its path inside.
// Vessel faces also add sign * mu, sign * d^2 and sign * d, for the trapezoid correction.
inline constexpr const char* kSceneVertex = R"(#ifdef GL_ES
precision highp float;
precision highp int;
#endif
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_attr;  // vessel: cell a, cell b, weight; tool: mu (1/mm), 0, 0
uniform mat4 u_view_proj;
uniform vec4 u_source;       // focal spot (mm), and the distance subtracted from every depth
uniform float u_tool;        // 0: vessel, 1: tool
uniform float u_iodine_mu;   // 1/mm per mgI/mL
#ifdef GL_ES
uniform highp sampler2D u_cells;  // cell i at (i % width, i / width)
float cell(float i) {
  int k = int(i);
  int w = textureSize(u_cells, 0).x;
  return texelFetch(u_cells, ivec2(k % w, k / w), 0).r;
}
#else
uniform samplerBuffer u_cells;
float cell(float i) { return texelFetch(u_cells, int(i)).r; }
#endif
out float v_mu;
out float v_d;
void main() {
  if (u_tool < 0.5) {
    v_mu = u_iodine_mu * mix(cell(in_attr.x), cell(in_attr.y), in_attr.z);
  } else {
    v_mu = in_attr.x;
  }
  v_d = distance(in_position, u_source.xyz) - u_source.w;
  gl_Position = u_view_proj * vec4(in_position, 1.0);
}
)";

inline constexpr const char* kSceneFragment = R"(#ifdef GL_ES
precision highp float;
#endif
in float v_mu;
in float v_d;
uniform float u_tool;
out vec4 frag;
void main() {
  float s = gl_FrontFacing ? -1.0 : 1.0;
  frag = u_tool < 0.5 ? vec4(s * v_mu * v_d, s * v_mu, s * v_d * v_d, s * v_d) : vec4(s * v_mu * v_d, 0.0, 0.0, 0.0);
}
)";

// Composite pass: the monitor's grey per pixel over the full-viewport triangle. MODE 0
// fluoroscopy, 1 fluoroscopy with the roadmap, 2 subtraction; SCENE 1 reads the scene targets, 0
// not (the native renderer draws outside the scenes' box with it: a software rasteriser runs both
// sides of a branch); FBFETCH 1 reads the phantom from the target being drawn
// (GL_EXT_shader_framebuffer_fetch, native only). The native renderer compiles all six, the page
// MODE 0-2 with SCENE 1.
inline constexpr const char* kCompositeFragment = R"(#ifndef FBFETCH
#define FBFETCH 0
#endif
#ifndef SCENE
#define SCENE 1
#endif
#ifdef GL_ES
precision highp float;
precision highp int;
precision highp sampler2D;
#endif
uniform sampler2D u_phantom;   // RG32F: L of the phantom, sqrt(T_ref / T) there; row 0 = the image's bottom row
uniform sampler2D u_live;      // scene targets (RGBA32F), row 0 = the image's bottom row
uniform sampler2D u_mask;
uniform sampler2D u_road;
uniform sampler2D u_road_mask;
uniform vec4 u_view;           // viewport origin (GL, bottom left) and size
uniform vec4 u_sigma;          // log-noise sigma at the reference transmission: live, mask, roadmap, roadmap mask
uniform uvec4 u_seeds;         // noise seeds (pulse_seed): live, mask, roadmap, roadmap mask
uniform vec4 u_display;        // fluoro slope, DSA background, DSA gain, roadmap gain
uniform vec4 u_mode;           // w: L_ref
uniform float u_field_half;    // half the collimated field, pixels
uniform float u_anatomy_gain;  // dynamic range compression of the phantom's part
#if FBFETCH
// The phantom texture is the target's first colour attachment (the monitor image the second): its texel under this fragment is
// read from the tile being drawn (llvmpipe: a load from the tile, not a texture fetch) and kept.
layout(location = 0) inout vec4 fb_phantom;
layout(location = 1) out vec4 frag;
#else
out vec4 frag;
#endif

float scene_L(sampler2D s, ivec2 p) {
#if SCENE
  vec4 v = texelFetch(s, p, 0);
  return abs(v.a) > 1e-4 ? v.r - v.g * v.b / (2.0 * v.a) : v.r;
#else
  return 0.0;  // outside every scene's box: no tool, no iodine
#endif
}
// pixel_noise() of fluoro_image_model.cpp: ~N(0, 1) from an integer hash of pixel and pulse.
float noise(uvec2 p, uint seed) {
  uint h = (p.x * 0x8DA6B343u) ^ (p.y * 0xD8163841u) ^ seed;
  h ^= h >> 16u;
  h *= 0x7FEB352Du;
  h ^= h >> 15u;
  h *= 0x846CA68Bu;
  h ^= h >> 16u;
  uint bytes = (h & 0xFFu) + ((h >> 8u) & 0xFFu) + ((h >> 16u) & 0xFFu) + (h >> 24u);
  return (float(bytes) - 510.0) * 0.0067659;
}
// The log image's noise at a pixel: sigma at the reference transmission times
// sqrt(T_ref / T) (`amp`, the phantom's transmission: contrast and tools are left out).
float noise_at(ivec2 p, uint seed, float sigma, float amp) {
  return sigma * amp * noise(uvec2(uint(p.x), uint(int(u_view.w) - 1 - p.y)), seed);
}
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy - u_view.xy);
  vec2 c = vec2(p) + 0.5 - 0.5 * u_view.zw;
  if (max(abs(c.x), abs(c.y)) > u_field_half) {
    frag = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
#if FBFETCH
  vec2 ph = fb_phantom.rg;
#else
  vec2 ph = texelFetch(u_phantom, p, 0).rg;
#endif
  float Lp = ph.x;
  float amp = ph.y;
  float L = Lp + scene_L(u_live, p);
  float g;
#if MODE == 2
  float Lm = Lp + scene_L(u_mask, p);
  float d = (L - noise_at(p, u_seeds.x, u_sigma.x, amp)) - (Lm - noise_at(p, u_seeds.y, u_sigma.y, amp));
  g = u_display.y - u_display.z * d;
#else
  float shown = u_mode.w + u_anatomy_gain * (Lp - u_mode.w) + (L - Lp);
  g = 1.0 / (1.0 + exp(-u_display.x * (u_mode.w - shown + noise_at(p, u_seeds.x, u_sigma.x, amp))));
#if MODE == 1
  float Lr = Lp + scene_L(u_road, p);
  float Lrm = Lp + scene_L(u_road_mask, p);
  float r = (Lr - noise_at(p, u_seeds.z, u_sigma.z, amp)) - (Lrm - noise_at(p, u_seeds.w, u_sigma.w, amp));
  g += (1.0 - clamp(g, 0.0, 1.0)) * (1.0 - exp(-u_display.w * r));
#endif
#endif
  frag = vec4(vec3(clamp(g, 0.0, 1.0)), 1.0);
}
)";

// The composite's and the scale pass's viewport-filling triangle (v_uv: 0..1 across it).
inline constexpr const char* kFullViewportVertex = R"(out vec2 v_uv;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  v_uv = p;
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
)";

// Scale pass: a binned monitor image scaled to the viewport, the full-viewport triangle sampling it
// bilinearly (a sampler with GL_LINEAR, clamped to its edge), as glBlitFramebuffer with GL_LINEAR
// maps it: each window pixel's centre at the same fraction of the image. On llvmpipe this costs
// ~6 ms of CPU at 1024^2 where the blit (Mesa's blitter) costs ~9.5 (README, "A binned image to
// the window").
inline constexpr const char* kScaleFragment = R"(#ifdef GL_ES
precision highp float;
#endif
in vec2 v_uv;
uniform sampler2D u_image;
out vec4 frag;
void main() { frag = texture(u_image, v_uv); }
)";

}  // namespace cathbox::app::fluoro_glsl
