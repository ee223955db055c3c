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

    const char *vs = "#version 300 es\nin vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }\n";
    const char *fs = slurp(argv[1]);
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
    glBindAttribLocation(program, 0, "p");
    glLinkProgram(program);
    glUseProgram(program);
    static const float triangle[] = {-1, -1, 3, -1, -1, 3};
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
