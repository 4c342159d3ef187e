#pragma once
// The GLSL programs of the GL backend (render/gl_renderer.cpp): the scene's vertex and fragment
// shaders (colour = clamp(exposure * (albedo * light + emission)), with per-pixel lamps when the
// light is not baked; instance id, class and camera-frame z written from the same fragments) and
// the mask that keeps a pass's unused pixels from being shaded. Internal to render/.

namespace corridorsim::render {

inline constexpr const char* kVertexShader = R"glsl(#version 330 core
layout(location = 0) in vec3 a_position;  // world frame, m
layout(location = 1) in vec3 a_normal;    // world frame
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec3 a_irradiance;  // ambient + baked lamps and bounces, RGB
uniform mat4 u_camera_from_world;
uniform mat4 u_clip_from_camera;
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
out vec3 v_camera;  // OpenCV optical frame, m
out vec3 v_irradiance;
void main() {
  vec4 p_in_camera = u_camera_from_world * vec4(a_position, 1.0);
  v_world = a_position;
  v_normal = a_normal;
  v_uv = a_uv;
  v_camera = p_in_camera.xyz;
  v_irradiance = a_irradiance;
  gl_Position = u_clip_from_camera * p_in_camera;
}
)glsl";

// Compiled once per light count (LIGHT_COUNT is prepended): llvmpipe runs a loop over a uniform
// count for every array slot, so a constant bound costs only the lights that are drawn.
inline constexpr const char* kFragmentShader = R"glsl(
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
in vec3 v_camera;
in vec3 v_irradiance;
uniform vec3 u_diffuse;
uniform float u_exposure;  // the camera's gain: 1 maps radiance 1 to full scale
uniform vec3 u_emission;
uniform int u_has_texture;
uniform sampler2D u_texture;
uniform float u_inv_falloff2;  // 1 / falloff^2, 1/m^2: a light's contribution halves at falloff
#if LIGHT_COUNT > 0
uniform vec3 u_light_position[LIGHT_COUNT];   // world frame, m
uniform vec3 u_light_intensity[LIGHT_COUNT];  // RGB
#endif
uniform uint u_instance;
uniform uint u_semantic;
layout(location = 0) out vec4 o_color;
layout(location = 1) out uint o_instance;
layout(location = 2) out uint o_semantic;
layout(location = 3) out float o_z;
void main() {
  vec3 base = u_diffuse;
  if (u_has_texture != 0) base *= texture(u_texture, v_uv).rgb;
  vec3 n = normalize(v_normal);
  vec3 light = v_irradiance;  // ambient (+ lamps and bounces when baked)
#if LIGHT_COUNT > 0
  for (int i = 0; i < LIGHT_COUNT; ++i) {
    // intensity * max(0, n.l) / (1 + (d / falloff)^2)
    vec3 to_light = u_light_position[i] - v_world;
    float d2 = max(dot(to_light, to_light), 1e-12);
    float n_dot_l = max(dot(n, to_light) * inversesqrt(d2), 0.0);
    light += u_light_intensity[i] * (n_dot_l / (1.0 + d2 * u_inv_falloff2));
  }
#endif
  o_color = vec4(clamp(u_exposure * (base * light + u_emission), 0.0, 1.0), 1.0);
  o_instance = u_instance;
  o_semantic = u_semantic;
  o_z = v_camera.z;  // exact for planar faces: perspective-correct interpolation of camera-frame z
}
)glsl";

// Marks a pass's unused pixels as nearest possible (depth 0) before the scene is drawn: llvmpipe
// tests depth before shading, so the scene's fragments there fail without being shaded.
inline constexpr const char* kMaskVertexShader = R"glsl(#version 330 core
layout(location = 0) in vec2 a_ndc;
void main() { gl_Position = vec4(a_ndc, -1.0, 1.0); }
)glsl";
inline constexpr const char* kMaskFragmentShader = R"glsl(#version 330 core
void main() {}
)glsl";

}  // namespace corridorsim::render
