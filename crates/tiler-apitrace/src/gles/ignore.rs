//! The ignore list: calls that change nothing tiler models, each with the reason.

const QUERY: &str = "reads state back; changes nothing that is drawn or stored";
const ERROR: &str = "reads the error flag";
const EGL_SETUP: &str = "EGL display and config setup; the surface and context calls carry what rendering needs";
const CURRENT: &str = "reads which context or surface is current; `eglMakeCurrent` sets it";
const PROC: &str = "looks up a function pointer";
const SWAP_INTERVAL: &str = "paces presentation; the image and its memory traffic are the same";
const VALIDATE: &str = "only sets the program's validate status, which only a query reads";
const RELEASE_COMPILER: &str = "a hint that the compiler's resources may be freed";
const DEBUG: &str = "debug labels, markers and callbacks; no effect on rendering";
const SYNC: &str = "a GPU-side wait (one context's commands run in order) or a sync object's query; \
                    fences and the CPU's waits are commands";

/// Every call on the ignore list, with why it is safe to ignore. They decode to
/// [`Command::Ignored`](super::Command::Ignored). `glGetUniformLocation`,
/// `glGetAttribLocation` and `glGetUniformBlockIndex` change nothing either but are not here:
/// their return values are the names later calls use, so they decode to their own variants.
pub const IGNORED: &[(&str, &str)] = &[
    ("glGetError", ERROR),
    ("glGetActiveAttrib", QUERY),
    ("glGetActiveUniform", QUERY),
    ("glGetActiveUniformBlockiv", QUERY),
    ("glGetActiveUniformBlockName", QUERY),
    ("glGetActiveUniformsiv", QUERY),
    ("glGetAttachedShaders", QUERY),
    ("glGetBooleanv", QUERY),
    ("glGetBufferParameteriv", QUERY),
    ("glGetBufferParameteri64v", QUERY),
    ("glGetBufferPointerv", QUERY),
    ("glGetBufferPointervOES", QUERY),
    ("glGetFloatv", QUERY),
    ("glGetFragDataLocation", QUERY),
    ("glGetFramebufferAttachmentParameteriv", QUERY),
    ("glGetInteger64v", QUERY),
    ("glGetIntegeri_v", QUERY),
    ("glGetInteger64i_v", QUERY),
    ("glGetIntegerv", QUERY),
    ("glGetInternalformativ", QUERY),
    ("glGetProgramInfoLog", QUERY),
    ("glGetProgramiv", QUERY),
    ("glGetQueryiv", QUERY),
    ("glGetQueryivEXT", QUERY),
    ("glGetRenderbufferParameteriv", QUERY),
    ("glGetSamplerParameterfv", QUERY),
    ("glGetSamplerParameteriv", QUERY),
    ("glGetShaderInfoLog", QUERY),
    ("glGetShaderPrecisionFormat", QUERY),
    ("glGetShaderSource", QUERY),
    ("glGetShaderiv", QUERY),
    ("glGetString", QUERY),
    ("glGetStringi", QUERY),
    ("glGetTexParameterfv", QUERY),
    ("glGetTexParameteriv", QUERY),
    ("glGetTexLevelParameteriv", QUERY),
    ("glGetTexLevelParameterfv", QUERY),
    ("glGetUniformIndices", QUERY),
    ("glGetUniformfv", QUERY),
    ("glGetUniformiv", QUERY),
    ("glGetUniformuiv", QUERY),
    ("glGetVertexAttribPointerv", QUERY),
    ("glGetVertexAttribfv", QUERY),
    ("glGetVertexAttribiv", QUERY),
    ("glCheckFramebufferStatus", QUERY),
    ("glIsBuffer", QUERY),
    ("glIsEnabled", QUERY),
    ("glIsFramebuffer", QUERY),
    ("glIsProgram", QUERY),
    ("glIsQuery", QUERY),
    ("glIsQueryEXT", QUERY),
    ("glIsRenderbuffer", QUERY),
    ("glIsSampler", QUERY),
    ("glIsShader", QUERY),
    ("glIsTexture", QUERY),
    ("glIsVertexArray", QUERY),
    ("glIsVertexArrayOES", QUERY),
    ("glValidateProgram", VALIDATE),
    ("glReleaseShaderCompiler", RELEASE_COMPILER),
    ("glDebugMessageCallback", DEBUG),
    ("glDebugMessageCallbackKHR", DEBUG),
    ("glDebugMessageControl", DEBUG),
    ("glDebugMessageControlKHR", DEBUG),
    ("glDebugMessageInsert", DEBUG),
    ("glDebugMessageInsertKHR", DEBUG),
    ("glInsertEventMarkerEXT", DEBUG),
    ("glObjectLabel", DEBUG),
    ("glObjectLabelKHR", DEBUG),
    ("glPopDebugGroup", DEBUG),
    ("glPopDebugGroupKHR", DEBUG),
    ("glPopGroupMarkerEXT", DEBUG),
    ("glPushDebugGroup", DEBUG),
    ("glPushDebugGroupKHR", DEBUG),
    ("glPushGroupMarkerEXT", DEBUG),
    ("eglGetError", ERROR),
    ("eglQueryString", QUERY),
    ("eglQueryContext", QUERY),
    ("eglQuerySurface", QUERY),
    ("eglQueryAPI", QUERY),
    ("eglGetConfigAttrib", QUERY),
    ("eglGetConfigs", EGL_SETUP),
    ("eglChooseConfig", EGL_SETUP),
    ("eglGetDisplay", EGL_SETUP),
    ("eglGetPlatformDisplay", EGL_SETUP),
    ("eglGetPlatformDisplayEXT", EGL_SETUP),
    ("eglInitialize", EGL_SETUP),
    ("eglTerminate", EGL_SETUP),
    ("eglBindAPI", EGL_SETUP),
    ("eglReleaseThread", EGL_SETUP),
    ("eglGetCurrentContext", CURRENT),
    ("eglGetCurrentDisplay", CURRENT),
    ("eglGetCurrentSurface", CURRENT),
    ("eglGetProcAddress", PROC),
    ("eglSwapInterval", SWAP_INTERVAL),
    ("glWaitSync", SYNC),
    ("glIsSync", QUERY),
    ("glGetSynciv", QUERY),
];

/// Functions of a feature tiler does not model, with the feature's name: their calls fail
/// with a message that says so rather than as unknown calls.
pub const NOT_MODELLED: &[(&[&str], &str)] = &[
    (
        &[
            "glCompressedTexImage3D",
            "glCompressedTexImage3DOES",
            "glCompressedTexSubImage3D",
            "glCompressedTexSubImage3DOES",
        ],
        "compressed 3-D and 2-D array textures",
    ),
    (&["glProgramBinary", "glProgramBinaryOES", "glShaderBinary"], "program binaries (tiler compiles GLSL source)"),
    (&["glDispatchCompute", "glDispatchComputeIndirect", "glMemoryBarrier"], "compute shaders (GL ES 3.1)"),
];

/// The feature `function` belongs to, if tiler does not model it; desktop OpenGL calls (ARB
/// entry points, immediate mode, GLX) are named as such.
pub fn not_modelled(function: &str) -> Option<&'static str> {
    if let Some((_, feature)) = NOT_MODELLED.iter().find(|(names, _)| names.contains(&function)) {
        return Some(feature);
    }
    let desktop = function.ends_with("ARB")
        || function.starts_with("glX")
        || ["glBegin", "glEnd", "glVertex2", "glVertex3", "glMatrixMode", "glLoadIdentity", "glPolygonMode"]
            .iter()
            .any(|p| function.starts_with(p) && !function.starts_with("glVertexAttrib"));
    desktop.then_some(
        "desktop OpenGL: tiler replays OpenGL ES / EGL captures (record a GLES context with `apitrace trace --api egl`)",
    )
}

/// Why `function` may be ignored, if it is on [`IGNORED`]; with its name as a `'static str`.
pub fn ignored(function: &str) -> Option<(&'static str, &'static str)> {
    IGNORED.iter().find(|(name, _)| *name == function).map(|(name, reason)| (*name, *reason))
}

#[cfg(test)]
mod tests {
    /// The crate documentation lists every ignored function (` (+KHR)` standing for both forms).
    #[test]
    fn the_crate_docs_list_every_ignored_function() {
        let docs = include_str!("../lib.rs").replace(" (+KHR)", "");
        for (name, _) in super::IGNORED {
            let base = name.strip_suffix("KHR").unwrap_or(name);
            assert!(docs.contains(base), "{name} is not in the crate docs' ignore list");
        }
    }
}
