#include "egl_context.hpp"

#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>

#include <cstdio>
#include <string>
#include <vector>

#include "foldcast/preview/preview.hpp"

namespace foldcast::preview {

namespace {

std::string egl_error_name(EGLint error) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04x", static_cast<unsigned>(error));
    return hex;
}

bool has_extension(const char* list, const std::string& name) {
    if (list == nullptr) return false;
    const std::string all = std::string(" ") + list + " ";
    return all.find(" " + name + " ") != std::string::npos;
}

// Initialised displays worth trying, best first.
std::vector<EGLDisplay> candidate_displays() {
    std::vector<EGLDisplay> displays;
    const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display == nullptr) return displays;
    if (has_extension(client_extensions, "EGL_MESA_platform_surfaceless"))
        displays.push_back(get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
    if (has_extension(client_extensions, "EGL_EXT_platform_device")) {
        auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        EGLint count = 0;
        EGLDeviceEXT devices[16];
        if (query_devices != nullptr && query_devices(16, devices, &count))
            for (EGLint i = 0; i < count; ++i)
                displays.push_back(get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr));
    }
    return displays;
}

}  // namespace

EglContext::EglContext() {
    std::string reasons;
    for (EGLDisplay display : candidate_displays()) {
        if (display == EGL_NO_DISPLAY) continue;
        EGLint major = 0, minor = 0;
        if (!eglInitialize(display, &major, &minor)) {
            reasons += " eglInitialize failed (" + egl_error_name(eglGetError()) + ");";
            continue;
        }
        if (!eglBindAPI(EGL_OPENGL_API)) {
            reasons += " no desktop OpenGL API;";
            eglTerminate(display);
            continue;
        }
        const EGLint attributes[] = {
            EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
        if (context == EGL_NO_CONTEXT) {
            reasons += " no OpenGL 3.3 core context (" + egl_error_name(eglGetError()) + ");";
            eglTerminate(display);
            continue;
        }
        if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
            reasons += " surfaceless eglMakeCurrent failed (" + egl_error_name(eglGetError()) + ");";
            eglDestroyContext(display, context);
            eglTerminate(display);
            continue;
        }
        display_ = display;
        context_ = context;
        description_ = std::string("OpenGL ") + reinterpret_cast<const char*>(glGetString(GL_VERSION)) + " on " +
                       reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        return;
    }
    if (reasons.empty())
        reasons = " no EGL display (neither EGL_MESA_platform_surfaceless nor EGL_EXT_platform_device)";
    throw EglUnavailable("EGL preview unavailable:" + reasons);
}

EglContext::~EglContext() {
    if (display_ == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
}

void EglContext::make_current() {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
        throw EglUnavailable("EGL preview: eglMakeCurrent failed (" + egl_error_name(eglGetError()) + ")");
}

}  // namespace foldcast::preview
