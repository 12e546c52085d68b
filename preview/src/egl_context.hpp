#pragma once
#include <EGL/egl.h>

#include <string>

namespace foldcast::preview {

// A current OpenGL 3.3 core context with no surface: rendering goes into FBOs.  Tries
// Mesa's surfaceless platform first, then every EGL device (EGL_EXT_platform_device),
// so it works on llvmpipe and on GPU drivers without a display.
class EglContext {
public:
    EglContext();  // throws EglUnavailable with the reason
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    void make_current();
    const std::string& description() const { return description_; }

private:
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    std::string description_;
};

}  // namespace foldcast::preview
