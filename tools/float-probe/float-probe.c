/* float-probe: renders one fragment shader over a 64x64 pbuffer on a headless EGL display
 * (EGL_PLATFORM_SURFACELESS_MESA: llvmpipe without X) and prints, for the first W x H pixels
 * (rows from y = 0 up), the float the shader packed into the pixel's bytes: the shader writes
 * the bits of one highp float per pixel as RGBA8 (see the README). Recording it with
 * `apitrace trace --api egl` gives a capture tiler replays (the pbuffer is its window), so the
 * same floats can be compared bit for bit.
 * Build: gcc -O1 -o float-probe float-probe.c -lEGL -lGLESv2
 * Run:   float-probe SHADER.frag W H */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *slurp(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) { perror(path); exit(1); }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *s = malloc(n + 1);
    if (fread(s, 1, n, f) != (size_t)n) { perror(path); exit(1); }
    s[n] = 0;
    fclose(f);
    return s;
}

int main(int argc, char **argv) {
    if (argc != 4) { fprintf(stderr, "usage: float-probe SHADER.frag W H\n"); return 2; }
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display = (void *)eglGetProcAddress("eglGetPlatformDisplayEXT");
    EGLDisplay dpy = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (!eglInitialize(dpy, NULL, NULL)) { fprintf(stderr, "eglInitialize failed\n"); return 1; }
    eglBindAPI(EGL_OPENGL_ES_API);
    EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT,
                               EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8, EGL_NONE};
    EGLConfig config;
    EGLint n;
    if (!eglChooseConfig(dpy, config_attribs, &config, 1, &n) || n == 0) { fprintf(stderr, "no config\n"); return 1; }
    EGLint pbuffer_attribs[] = {EGL_WIDTH, 64, EGL_HEIGHT, 64, EGL_NONE};
    EGLSurface surface = eglCreatePbufferSurface(dpy, config, pbuffer_attribs);
    EGLint context_attribs[] = {EGL_CONTEXT_CLIENT_VERSION, 3, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, context_attribs);
    eglMakeCurrent(dpy, surface, surface, ctx);

    /* `v` is a varying with irregular slopes, for shaders that probe interpolation. */
    /* The vertex shader takes the fragment shader's version (a program's must match). */
    const char *fs = slurp(argv[1]);
    const char *vs = strncmp(fs, "#version 310 es", 15) == 0
        ? "#version 310 es\nin vec2 p;\nin float w;\nout highp vec2 v;\n"
          "void main() { v = p * vec2(0.3183099, 0.2718282) + vec2(0.1234567, 0.7654321);\n"
          "  gl_Position = vec4(p * w, 0.0, w); }\n"
        : "#version 300 es\nin vec2 p;\nin float w;\nout highp vec2 v;\n"
                     "void main() { v = p * vec2(0.3183099, 0.2718282) + vec2(0.1234567, 0.7654321);\n"
                     "  gl_Position = vec4(p * w, 0.0, w); }\n";
    GLuint v = glCreateShader(GL_VERTEX_SHADER), f = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(v, 1, &vs, NULL);
    glCompileShader(v);
    glShaderSource(f, 1, &fs, NULL);
    glCompileShader(f);
    char log[4096] = "";
    glGetShaderInfoLog(f, sizeof log, NULL, log);
    if (log[0]) fprintf(stderr, "%s\n", log);
    GLuint program = glCreateProgram();
    glAttachShader(program, v);
    glAttachShader(program, f);
    /* FLOAT_PROBE_TEXTURE=upload: an 8×8 RGBA8 texture on unit 0 whose texel (x, y) (y = 0
     * the first row uploaded) has red 30x + y, green 30y + x; =render: the same texels drawn
     * into a texture through a framebuffer. Nearest filtering, clamped.
     * =varied: an 8×8 RGBA8 texture of bytes from a linear congruential generator, with its
     * levels 4×4, 2×2 and 1×1 uploaded likewise (the generator running on), so that filtered
     * values show every weight; =varied-npot: a 7×5 one, level 0 only.
     * FLOAT_PROBE_FILTER=linear filters linearly (LINEAR_MIPMAP_LINEAR with levels) instead of
     * nearest; FLOAT_PROBE_WRAP=repeat|clamp|mirror sets both wraps (clamp-to-edge unless set);
     * FLOAT_PROBE_MIN=nearest-mipmap-nearest|linear-mipmap-nearest|nearest-mipmap-linear sets
     * the minification filter (the magnification filter stays as FLOAT_PROBE_FILTER says). */
    const char *texture = getenv("FLOAT_PROBE_TEXTURE");
    if (texture && strncmp(texture, "varied", 6) == 0) {
        int npot = strcmp(texture, "varied-npot") == 0;
        int width = npot ? 7 : 8, height = npot ? 5 : 8, levels = npot ? 1 : 4;
        const char *filter = getenv("FLOAT_PROBE_FILTER");
        const char *wrap = getenv("FLOAT_PROBE_WRAP");
        int linear = filter && strcmp(filter, "linear") == 0;
        GLint wrap_mode = !wrap || strcmp(wrap, "clamp") == 0 ? GL_CLAMP_TO_EDGE
                        : strcmp(wrap, "repeat") == 0       ? GL_REPEAT
                                                              : GL_MIRRORED_REPEAT;
        GLuint tex;
        glGenTextures(1, &tex);
        glBindTexture(GL_TEXTURE_2D, tex);
        const char *min = getenv("FLOAT_PROBE_MIN");
        GLint min_filter = linear ? (levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR) : GL_NEAREST;
        if (min && strcmp(min, "nearest-mipmap-nearest") == 0) min_filter = GL_NEAREST_MIPMAP_NEAREST;
        if (min && strcmp(min, "linear-mipmap-nearest") == 0) min_filter = GL_LINEAR_MIPMAP_NEAREST;
        if (min && strcmp(min, "nearest-mipmap-linear") == 0) min_filter = GL_NEAREST_MIPMAP_LINEAR;
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, min_filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, linear ? GL_LINEAR : GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap_mode);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap_mode);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
        static unsigned char bytes[8 * 8 * 4];
        unsigned state = 12345;
        for (int level = 0; level < levels; level++) {
            int w = width >> level, h = height >> level;
            for (int i = 0; i < w * h * 4; i++) {
                state = state * 1103515245u + 12345u;
                bytes[i] = state >> 16;
            }
            glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
            glTexImage2D(GL_TEXTURE_2D, level, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, bytes);
        }
    } else if (texture) {
        static unsigned char texels[8 * 8 * 4];
        for (int y = 0; y < 8; y++)
            for (int x = 0; x < 8; x++) {
                unsigned char *t = texels + (y * 8 + x) * 4;
                t[0] = 30 * x + y; t[1] = 30 * y + x; t[2] = 0; t[3] = 255;
            }
        GLuint tex;
        glGenTextures(1, &tex);
        glBindTexture(GL_TEXTURE_2D, tex);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        int render = strcmp(texture, "render") == 0;
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 8, 8, 0, GL_RGBA, GL_UNSIGNED_BYTE, render ? NULL : texels);
        if (render) {
            const char *fill_vs = "#version 300 es\nin vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }\n";
            const char *fill_fs = "#version 300 es\nprecision highp float;\nout vec4 color;\n"
                                  "void main() { vec2 c = floor(gl_FragCoord.xy);\n"
                                  "  color = vec4(30.0 * c.x + c.y, 30.0 * c.y + c.x, 0.0, 255.0) / 255.0; }\n";
            GLuint fv = glCreateShader(GL_VERTEX_SHADER), ff = glCreateShader(GL_FRAGMENT_SHADER);
            glShaderSource(fv, 1, &fill_vs, NULL);
            glCompileShader(fv);
            glShaderSource(ff, 1, &fill_fs, NULL);
            glCompileShader(ff);
            GLuint fill = glCreateProgram();
            glAttachShader(fill, fv);
            glAttachShader(fill, ff);
            glBindAttribLocation(fill, 0, "p");
            glLinkProgram(fill);
            glUseProgram(fill);
            GLuint fb;
            glGenFramebuffers(1, &fb);
            glBindFramebuffer(GL_FRAMEBUFFER, fb);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
            static const float full[] = {-1, -1, 3, -1, -1, 3};
            glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, full);
            glEnableVertexAttribArray(0);
            glViewport(0, 0, 8, 8);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
        }
    }
    glBindAttribLocation(program, 0, "p");
    glBindAttribLocation(program, 1, "w");
    glLinkProgram(program);
    glUseProgram(program);
    /* The triangle covering the window; FLOAT_PROBE_TRIANGLE="x0 y0 x1 y1 x2 y2" (clip
     * coordinates) draws another, e.g. one inside the window, which llvmpipe does not clip. */
    static float triangle[] = {-1, -1, 3, -1, -1, 3};
    const char *custom = getenv("FLOAT_PROBE_TRIANGLE");
    if (custom && sscanf(custom, "%f %f %f %f %f %f", &triangle[0], &triangle[1], &triangle[2], &triangle[3],
                         &triangle[4], &triangle[5]) != 6) {
        fprintf(stderr, "FLOAT_PROBE_TRIANGLE: six numbers expected\n");
        return 2;
    }
    /* Each vertex's clip w (1 unless FLOAT_PROBE_W="w0 w1 w2"): perspective interpolation. */
    static float clip_w[] = {1, 1, 1};
    const char *custom_w = getenv("FLOAT_PROBE_W");
    if (custom_w && sscanf(custom_w, "%f %f %f", &clip_w[0], &clip_w[1], &clip_w[2]) != 3) {
        fprintf(stderr, "FLOAT_PROBE_W: three numbers expected\n");
        return 2;
    }
    glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 0, clip_w);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, triangle);
    glEnableVertexAttribArray(0);
    glViewport(0, 0, 64, 64);
    glDisable(GL_DITHER);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    static unsigned char pixels[64 * 64 * 4];
    glReadPixels(0, 0, 64, 64, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    int w = atoi(argv[2]), h = atoi(argv[3]);
    for (int y = 0; y < h && y < 64; y++) {
        for (int x = 0; x < w && x < 64; x++) {
            const unsigned char *q = pixels + (y * 64 + x) * 4;
            unsigned bits = (unsigned)q[0] << 24 | q[1] << 16 | q[2] << 8 | q[3];
            float value;
            memcpy(&value, &bits, 4);
            printf("%08x%c", bits, x + 1 < w ? ' ' : '\n');
            (void)value;
        }
    }
    return 0;
}
