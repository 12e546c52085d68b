#pragma once
// GLSL 3.30 core sources of the preview rasteriser.

namespace foldcast::preview::shaders {

inline constexpr const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
uniform mat4 u_light_view_proj;
out vec3 v_position;
out vec3 v_normal;
out vec4 v_light_clip;
void main() {
    v_position = a_position;
    v_normal = a_normal;
    v_light_clip = u_light_view_proj * vec4(a_position, 1.0);
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";

// Lambert + Charlie sheen (Estevez-Kulla, Neubelt visibility) + GGX (height-correlated
// Smith), key-light shadows by 3x3 PCF widened by the light's size.  Cloth is two-sided:
// normals face the viewer.  Writes linear radiance into a float target, like the path
// tracer's beauty image.
//
// The source is compiled once per light count: the caller prepends "#version 330 core" and
// "#define LIGHT_COUNT n".  llvmpipe runs a loop over a uniform count, and a texture fetch
// under a branch, with every lane masked, which made frames 40 % slower than this unrolled,
// branch-free form (bench/bench_preview_turntable.sh).
inline constexpr const char* kShadeBody = R"(
in vec3 v_position;
in vec3 v_normal;
in vec4 v_light_clip;
uniform vec3 u_camera;
#if LIGHT_COUNT > 0
uniform vec3 u_light_position[LIGHT_COUNT];
uniform vec3 u_light_intensity[LIGHT_COUNT];
#endif
uniform vec3 u_base;
uniform float u_roughness;
uniform vec3 u_sheen;
uniform float u_sheen_roughness;
uniform float u_specular;
uniform vec3 u_ambient;
uniform sampler2DShadow u_shadow_map;  // border depth 1: outside the key's frustum is lit
uniform float u_has_shadow;            // 0 or 1
uniform float u_shadow_step;           // PCF tap spacing in texture coordinates
layout(location = 0) out vec4 o_colour;
const float PI = 3.14159265358979;

float key_light_visibility() {
    vec3 p = v_light_clip.xyz / v_light_clip.w * 0.5 + 0.5;
    float z = p.z - 0.0015;
    // 3x3 taps spread over the penumbra; each tap is itself bilinearly filtered (PCF), so
    // the result stays smooth.
    float lit = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            lit += texture(u_shadow_map, vec3(p.xy + vec2(x, y) * u_shadow_step, z));
    // Past the shadow frustum's far plane nothing is known to occlude: lit.
    float inside = u_has_shadow * step(p.z, 1.0);
    return mix(1.0, lit / 9.0, inside);
}
float ggx_d(float ndh, float a) {
    float a2 = a * a;
    float d = ndh * ndh * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}
float smith_v(float ndl, float ndv, float a) {
    float a2 = a * a;
    float gl = ndv * sqrt(ndl * ndl * (1.0 - a2) + a2);
    float gv = ndl * sqrt(ndv * ndv * (1.0 - a2) + a2);
    return 0.5 / (gl + gv + 1e-7);
}
float charlie_d(float ndh, float r) {
    float inv = 1.0 / max(r, 0.02);
    float sin2 = max(1.0 - ndh * ndh, 1e-7);
    return (2.0 + inv) * pow(sin2, 0.5 * inv) / (2.0 * PI);
}
float neubelt_v(float ndl, float ndv) { return 1.0 / (4.0 * (ndl + ndv - ndl * ndv) + 1e-7); }
void main() {
    vec3 v = normalize(u_camera - v_position);
    vec3 n = normalize(v_normal);
    if (dot(n, v) < 0.0) n = -n;
    float ndv = max(dot(n, v), 1e-4);
    float a = max(u_roughness * u_roughness, 0.002);
    vec3 f0 = vec3(0.08 * u_specular);
    float sheen_max = max(u_sheen.r, max(u_sheen.g, u_sheen.b));
    vec3 diffuse = u_base / PI * (1.0 - 0.5 * sheen_max);
    vec3 radiance = u_ambient * u_base;
#if LIGHT_COUNT > 0
    float key_visibility = key_light_visibility();
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        vec3 l = u_light_position[i] - v_position;
        float d2 = dot(l, l);
        l *= inversesqrt(d2);
        float ndl = max(dot(n, l), 0.0);  // zero from behind: no contribution
        vec3 h = normalize(l + v);
        float ndh = max(dot(n, h), 0.0);
        vec3 fresnel = f0 + (1.0 - f0) * pow(1.0 - max(dot(v, h), 0.0), 5.0);
        vec3 specular = fresnel * ggx_d(ndh, a) * smith_v(ndl, ndv, a);
        vec3 sheen = u_sheen * charlie_d(ndh, u_sheen_roughness) * neubelt_v(ndl, ndv);
        vec3 irradiance = u_light_intensity[i] * (ndl / d2);
        if (i == 0) irradiance *= key_visibility;
        radiance += (diffuse + specular + sheen) * irradiance;
    }
#endif
    o_colour = vec4(radiance, 1.0);  // linear: exposure and sRGB are applied on output
}
)";

// Distance from the camera, for the depth image.
inline constexpr const char* kDistance = R"(#version 330 core
in vec3 v_position;
in vec3 v_normal;
in vec4 v_light_clip;
uniform vec3 u_camera;
layout(location = 0) out float o_distance;
void main() { o_distance = length(v_position - u_camera); }
)";

// Shadow map: depth only.
inline constexpr const char* kEmpty = R"(#version 330 core
void main() {}
)";

}  // namespace foldcast::preview::shaders
