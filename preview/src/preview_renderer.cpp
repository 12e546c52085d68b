#include <Eigen/Geometry>
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "egl_context.hpp"
#include "foldcast/preview/preview.hpp"
#include "preview_shaders.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::preview {

namespace {

constexpr int kMinShadowMapSize = 256;
constexpr int kMaxShadowMapSize = 2048;
constexpr int kMaxLights = 4;
constexpr float kEmptyDistance = 1e30f;  // cleared distance; read back as +inf

Eigen::Matrix4f look_at(const Vec3f& eye, const Vec3f& target, const Vec3f& up) {
    const Vec3f f = (target - eye).normalized();
    Vec3f s = f.cross(up);
    if (s.squaredNorm() < 1e-12f) s = f.cross(Vec3f(1.0f, 0.0f, 0.0f));
    s.normalize();
    const Vec3f u = s.cross(f);
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -s.dot(eye);
    m(1, 3) = -u.dot(eye);
    m(2, 3) = f.dot(eye);
    return m;
}

Eigen::Matrix4f perspective(float vertical_fov_rad, float aspect, float near_m, float far_m) {
    const float f = 1.0f / std::tan(vertical_fov_rad / 2.0f);
    Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
    m(0, 0) = f / aspect;
    m(1, 1) = f;
    m(2, 2) = (far_m + near_m) / (near_m - far_m);
    m(2, 3) = 2.0f * far_m * near_m / (near_m - far_m);
    m(3, 2) = -1.0f;
    return m;
}

void check_gl(const char* what) {
    const GLenum error = glGetError();
    if (error != GL_NO_ERROR)
        throw std::runtime_error(std::string("OpenGL error during ") + what + ": " + std::to_string(error));
}

GLuint compile(GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        throw std::runtime_error(std::string("preview shader does not compile: ") + log);
    }
    return shader;
}

GLuint link_program(const char* vertex, const char* fragment) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment);
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        glDeleteProgram(program);
        throw std::runtime_error(std::string("preview shaders do not link: ") + log);
    }
    return program;
}

struct GpuMesh {
    GLuint vao = 0, vbo = 0, ebo = 0;
    GLsizei index_count = 0;
    bool casts_shadow = true;
    const PreviewMaterial* material = nullptr;
};

GpuMesh upload(const PreviewObject& object) {
    const Mesh& mesh = *object.mesh;
    const std::vector<Vec3f> normals = mesh.normals.size() == mesh.positions.size()
                                           ? mesh.normals
                                           : vertex_normals(mesh.positions, mesh.topology.triangles);
    std::vector<float> interleaved;
    interleaved.reserve(mesh.positions.size() * 6);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        interleaved.insert(interleaved.end(), mesh.positions[i].data(), mesh.positions[i].data() + 3);
        interleaved.insert(interleaved.end(), normals[i].data(), normals[i].data() + 3);
    }
    GpuMesh gpu;
    gpu.casts_shadow = object.casts_shadow;
    gpu.material = &object.material;
    gpu.index_count = static_cast<GLsizei>(mesh.topology.triangles.size() * 3);
    glGenVertexArrays(1, &gpu.vao);
    glBindVertexArray(gpu.vao);
    glGenBuffers(1, &gpu.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, gpu.vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data(),
                 GL_STREAM_DRAW);
    glGenBuffers(1, &gpu.ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.topology.triangles.size() * sizeof(Triangle)),
                 mesh.topology.triangles.data(), GL_STREAM_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                          reinterpret_cast<const void*>(3 * sizeof(float)));
    glBindVertexArray(0);
    return gpu;
}

void release(GpuMesh& gpu) {
    glDeleteBuffers(1, &gpu.vbo);
    glDeleteBuffers(1, &gpu.ebo);
    glDeleteVertexArrays(1, &gpu.vao);
}

void draw(const GpuMesh& gpu) {
    glBindVertexArray(gpu.vao);
    glDrawElements(GL_TRIANGLES, gpu.index_count, GL_UNSIGNED_INT, nullptr);
}

GLint uniform(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

// A renderbuffer of `format` attached to the bound framebuffer; samples > 0 makes it multisampled.
GLuint attach_renderbuffer(GLenum attachment, GLenum format, int samples, int width, int height) {
    GLuint buffer = 0;
    glGenRenderbuffers(1, &buffer);
    glBindRenderbuffer(GL_RENDERBUFFER, buffer);
    if (samples > 0)
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, width, height);
    else
        glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, buffer);
    return buffer;
}

// The scene's bounding sphere: it fixes the depth range and the key light's far plane.
struct SceneBounds {
    Vec3f centre;
    float radius;
};

SceneBounds scene_bounds(const PreviewScene& scene) {
    Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::max());
    Vec3f hi = -lo;
    for (const PreviewObject& object : scene.objects)
        for (const Vec3f& p : object.mesh->positions) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
    if (scene.objects.empty()) lo = hi = Vec3f::Zero();
    return {0.5f * (lo + hi), std::max(0.5f * (hi - lo).norm(), 1e-3f)};
}

Eigen::Matrix4f camera_view_proj(const PreviewCamera& camera, const SceneBounds& bounds, int width, int height) {
    const float to_centre = (bounds.centre - camera.position).norm();
    const float near_m = std::max(to_centre - 1.05f * bounds.radius, 1e-3f * bounds.radius);
    const float far_m = to_centre + 1.05f * bounds.radius;
    const float fov = camera.vertical_fov_deg * kPiF / 180.0f;
    return perspective(fov, static_cast<float>(width) / static_cast<float>(height), near_m, far_m) *
           look_at(camera.position, camera.target, camera.up);
}

// The key light's shadow map: its frustum, size and PCF tap spacing.
struct ShadowSetup {
    Eigen::Matrix4f light_view_proj = Eigen::Matrix4f::Identity();
    bool has_shadow = false;
    int map_size = kMinShadowMapSize;
    float step = 0.0f;  // PCF tap spacing in texture coordinates
};

// The key light's shadow frustum covers the shadow casters only (receivers outside it
// are lit), so a large backdrop does not dilute the shadow map's resolution.
ShadowSetup shadow_setup(const PreviewScene& scene, float radius) {
    Vec3f caster_lo = Vec3f::Constant(std::numeric_limits<float>::max());
    Vec3f caster_hi = -caster_lo;
    for (const PreviewObject& object : scene.objects)
        if (object.casts_shadow)
            for (const Vec3f& p : object.mesh->positions) {
                caster_lo = caster_lo.cwiseMin(p);
                caster_hi = caster_hi.cwiseMax(p);
            }
    ShadowSetup out;
    if (scene.lights.empty() || !(caster_lo.x() <= caster_hi.x())) return out;
    const Vec3f caster_centre = 0.5f * (caster_lo + caster_hi);
    const float caster_radius = std::max(0.5f * (caster_hi - caster_lo).norm(), 1e-3f);
    const Vec3f key = scene.lights.front().position;
    const float distance = (caster_centre - key).norm();
    if (!(distance > caster_radius * 1.01f)) return out;
    const float half_angle = std::asin(std::min(caster_radius / distance, 0.99f)) * 1.05f;
    // The far plane reaches past the casters so receivers behind them compare correctly.
    out.light_view_proj = perspective(2.0f * half_angle, 1.0f, distance - caster_radius, distance + 4.0f * radius) *
                          look_at(key, caster_centre,
                                  std::abs((caster_centre - key).normalized().y()) > 0.99f ? Vec3f(1.0f, 0.0f, 0.0f)
                                                                                           : Vec3f(0.0f, 1.0f, 0.0f));
    out.has_shadow = true;
    // An area light's penumbra: about size/distance of the gap between occluder and
    // receiver, taken at a typical fold-to-fold gap of 5 cm.  The 3x3 taps span it, one
    // texel apart where the map's size allows, so the bilinear taps blend smoothly.
    const float penumbra_m = scene.lights.front().size_m / distance * 0.05f;
    const float frustum_m = 2.0f * std::tan(half_angle) * distance;
    const float wanted = std::ceil(frustum_m / std::max(0.5f * penumbra_m, 1e-6f) / 32.0f) * 32.0f;
    out.map_size = static_cast<int>(std::clamp(wanted, float(kMinShadowMapSize), float(kMaxShadowMapSize)));
    const float texel_m = frustum_m / out.map_size;
    out.step = std::clamp(0.5f * penumbra_m / texel_m, 1.0f, 24.0f) / out.map_size;
    return out;
}

// The read-back colour and distance as an image: OpenGL's rows run bottom-up, images top-down.
PreviewImage image_from_rows(int width, int height, const std::vector<float>& rgba,
                             const std::vector<float>& distance) {
    PreviewImage image;
    image.width = width;
    image.height = height;
    const std::size_t row = static_cast<std::size_t>(width);
    image.rgba.resize(rgba.size());
    image.depth.resize(distance.size());  // empty without a depth pass
    for (int y = 0; y < height; ++y) {
        const std::size_t from = static_cast<std::size_t>(height - 1 - y) * row;
        const std::size_t to = static_cast<std::size_t>(y) * row;
        std::copy_n(rgba.begin() + 4 * from, 4 * row, image.rgba.begin() + 4 * to);
        for (std::size_t x = 0; x < distance.size() / height; ++x) {
            const float d = distance[from + x];
            image.depth[to + x] = d >= 0.5f * kEmptyDistance ? std::numeric_limits<float>::infinity() : d;
        }
    }
    return image;
}

}  // namespace

struct PreviewRenderer::State {
    EglContext egl;
    int width = 0, height = 0, samples = 0;
    std::array<GLuint, kMaxLights + 1> shade_programs{};  // by light count, linked on first use
    GLuint distance_program = 0, shadow_program = 0;
    GLuint msaa_fbo = 0, msaa_colour = 0, msaa_depth = 0;
    GLuint resolve_fbo = 0, resolve_colour = 0;
    GLuint distance_fbo = 0, distance_colour = 0, distance_depth = 0;
    GLuint shadow_fbo = 0, shadow_map = 0;
    int shadow_map_size = 0;

    GLuint shade_program(int light_count) {
        GLuint& program = shade_programs.at(static_cast<std::size_t>(light_count));
        if (program == 0) {
            const std::string source =
                "#version 330 core\n#define LIGHT_COUNT " + std::to_string(light_count) + "\n" + shaders::kShadeBody;
            program = link_program(shaders::kVertex, source.c_str());
        }
        return program;
    }

    // The shadow map's texels are sized to the penumbra, so it stays small (and in cache)
    // for the large soft lights of a studio; reallocated only when the size changes.
    void size_shadow_map(int size) {
        if (size == shadow_map_size) return;
        glBindTexture(GL_TEXTURE_2D, shadow_map);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, size, size, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
        shadow_map_size = size;
    }
};

PreviewRenderer::PreviewRenderer(int width, int height, int msaa_samples) : state_(std::make_unique<State>()) {
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
        throw std::invalid_argument("preview size must be in 1..16384 pixels");
    State& s = *state_;
    s.width = width;
    s.height = height;
    GLint max_samples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    s.samples = std::clamp(msaa_samples, 1, std::max(1, static_cast<int>(max_samples)));

    s.distance_program = link_program(shaders::kVertex, shaders::kDistance);
    s.shadow_program = link_program(shaders::kVertex, shaders::kEmpty);

    glGenFramebuffers(1, &s.msaa_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, s.msaa_fbo);
    s.msaa_colour = attach_renderbuffer(GL_COLOR_ATTACHMENT0, GL_RGBA16F, s.samples, width, height);
    s.msaa_depth = attach_renderbuffer(GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, s.samples, width, height);

    glGenFramebuffers(1, &s.resolve_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, s.resolve_fbo);
    s.resolve_colour = attach_renderbuffer(GL_COLOR_ATTACHMENT0, GL_RGBA16F, 0, width, height);

    glGenFramebuffers(1, &s.distance_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, s.distance_fbo);
    s.distance_colour = attach_renderbuffer(GL_COLOR_ATTACHMENT0, GL_R32F, 0, width, height);
    s.distance_depth = attach_renderbuffer(GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, 0, width, height);

    glGenFramebuffers(1, &s.shadow_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, s.shadow_fbo);
    glGenTextures(1, &s.shadow_map);
    glBindTexture(GL_TEXTURE_2D, s.shadow_map);
    s.size_shadow_map(kMinShadowMapSize);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    // Outside the key light's frustum nothing casts a shadow: the border compares as lit.
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    const float far_depth[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, far_depth);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, s.shadow_map, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);

    for (GLuint fbo : {s.msaa_fbo, s.resolve_fbo, s.distance_fbo, s.shadow_fbo}) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw EglUnavailable("EGL preview: the OpenGL driver cannot make the framebuffers it needs");
    }
    check_gl("framebuffer setup");
}

PreviewRenderer::~PreviewRenderer() {
    State& s = *state_;
    for (GLuint program : s.shade_programs)
        if (program != 0) glDeleteProgram(program);
    glDeleteProgram(s.distance_program);
    glDeleteProgram(s.shadow_program);
    const GLuint fbos[] = {s.msaa_fbo, s.resolve_fbo, s.distance_fbo, s.shadow_fbo};
    glDeleteFramebuffers(4, fbos);
    const GLuint rbs[] = {s.msaa_colour, s.msaa_depth, s.resolve_colour, s.distance_colour, s.distance_depth};
    glDeleteRenderbuffers(5, rbs);
    glDeleteTextures(1, &s.shadow_map);
}

const std::string& PreviewRenderer::device_description() const { return state_->egl.description(); }

PreviewImage PreviewRenderer::render(const PreviewScene& scene) {
    State& s = *state_;
    s.egl.make_current();

    const SceneBounds bounds = scene_bounds(scene);
    const PreviewCamera& camera = scene.camera;
    const Eigen::Matrix4f view_proj = camera_view_proj(camera, bounds, s.width, s.height);
    const ShadowSetup shadow = shadow_setup(scene, bounds.radius);
    const Eigen::Matrix4f& light_view_proj = shadow.light_view_proj;
    const bool has_shadow = shadow.has_shadow;
    const int shadow_map_size = shadow.map_size;
    const float shadow_step = shadow.step;

    std::vector<GpuMesh> meshes;
    meshes.reserve(scene.objects.size());
    for (const PreviewObject& object : scene.objects) meshes.push_back(upload(object));

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);

    if (has_shadow) {
        glBindFramebuffer(GL_FRAMEBUFFER, s.shadow_fbo);
        s.size_shadow_map(shadow_map_size);
        glViewport(0, 0, shadow_map_size, shadow_map_size);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(s.shadow_program);
        glUniformMatrix4fv(uniform(s.shadow_program, "u_view_proj"), 1, GL_FALSE, light_view_proj.data());
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.5f, 2.0f);
        for (const GpuMesh& mesh : meshes)
            if (mesh.casts_shadow) draw(mesh);
        glDisable(GL_POLYGON_OFFSET_FILL);
    }

    glBindFramebuffer(GL_FRAMEBUFFER, s.msaa_fbo);
    glViewport(0, 0, s.width, s.height);
    glEnable(GL_MULTISAMPLE);
    const float alpha = scene.transparent_background ? 0.0f : 1.0f;
    glClearColor(scene.background.x(), scene.background.y(), scene.background.z(), alpha);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const int light_count = std::min<int>(static_cast<int>(scene.lights.size()), kMaxLights);
    const GLuint p = s.shade_program(light_count);
    glUseProgram(p);
    glUniformMatrix4fv(uniform(p, "u_view_proj"), 1, GL_FALSE, view_proj.data());
    glUniformMatrix4fv(uniform(p, "u_light_view_proj"), 1, GL_FALSE, light_view_proj.data());
    glUniform3fv(uniform(p, "u_camera"), 1, camera.position.data());
    for (int i = 0; i < light_count; ++i) {
        const char index[] = {'[', static_cast<char>('0' + i), ']', '\0'};
        glUniform3fv(uniform(p, (std::string("u_light_position") + index).c_str()), 1, scene.lights[i].position.data());
        glUniform3fv(uniform(p, (std::string("u_light_intensity") + index).c_str()), 1,
                     scene.lights[i].intensity.data());
    }
    glUniform3fv(uniform(p, "u_ambient"), 1, scene.ambient.data());
    glUniform1f(uniform(p, "u_has_shadow"), has_shadow ? 1.0f : 0.0f);
    glUniform1f(uniform(p, "u_shadow_step"), shadow_step);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, s.shadow_map);
    glUniform1i(uniform(p, "u_shadow_map"), 0);
    for (const GpuMesh& mesh : meshes) {
        const PreviewMaterial& m = *mesh.material;
        glUniform3fv(uniform(p, "u_base"), 1, m.base_colour.data());
        glUniform1f(uniform(p, "u_roughness"), m.roughness);
        glUniform3fv(uniform(p, "u_sheen"), 1, m.sheen_colour.data());
        glUniform1f(uniform(p, "u_sheen_roughness"), m.sheen_roughness);
        glUniform1f(uniform(p, "u_specular"), m.specular);
        draw(mesh);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, s.msaa_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, s.resolve_fbo);
    glBlitFramebuffer(0, 0, s.width, s.height, 0, 0, s.width, s.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);

    // Distance pass without MSAA: a depth image must not average across silhouettes.
    if (scene.want_depth) {
        glBindFramebuffer(GL_FRAMEBUFFER, s.distance_fbo);
        const float empty[4] = {kEmptyDistance, 0.0f, 0.0f, 0.0f};
        glClearBufferfv(GL_COLOR, 0, empty);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(s.distance_program);
        glUniformMatrix4fv(uniform(s.distance_program, "u_view_proj"), 1, GL_FALSE, view_proj.data());
        glUniform3fv(uniform(s.distance_program, "u_camera"), 1, camera.position.data());
        for (const GpuMesh& mesh : meshes) draw(mesh);
    }

    std::vector<float> rgba(static_cast<std::size_t>(s.width) * s.height * 4);
    std::vector<float> distance(scene.want_depth ? static_cast<std::size_t>(s.width) * s.height : 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, s.resolve_fbo);
    glReadPixels(0, 0, s.width, s.height, GL_RGBA, GL_FLOAT, rgba.data());
    if (scene.want_depth) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, s.distance_fbo);
        glReadPixels(0, 0, s.width, s.height, GL_RED, GL_FLOAT, distance.data());
    }
    check_gl("preview rendering");
    for (GpuMesh& mesh : meshes) release(mesh);

    return image_from_rows(s.width, s.height, rgba, distance);
}

}  // namespace foldcast::preview
