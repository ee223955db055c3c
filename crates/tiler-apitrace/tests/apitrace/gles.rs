//! The typed layer on generated captures: decoding, fake calls, mapped-buffer writes, errors.

use tiler_apitrace::gles::consts::*;
use tiler_apitrace::gles::{Command, DecodeErrorKind, Error, GlesCall, GlesReader, IGNORED, Memory, UniformValue};
use tiler_apitrace::wire::Limits;

use crate::writer::{W, Writer};

fn decode(writer: &Writer) -> Result<Vec<GlesCall>, Error> {
    GlesReader::new(&writer.snappy(1 << 20)[..], Limits::DEFAULT).unwrap().collect()
}

fn commands(writer: &Writer) -> Vec<Command> {
    decode(writer).unwrap().into_iter().map(|call| call.command).collect()
}

fn gl_enum(name: &'static str, value: GlEnum) -> W {
    W::gl_enum(name, value as i64)
}

use tiler_apitrace::gles::GlEnum;

#[test]
fn an_unknown_call_is_an_error_naming_its_number_and_function() {
    let mut writer = Writer::new(6);
    writer.call("glFlush", &[], None, false);
    writer.call("glFrobnicate", &[("target", W::UInt(0x806f))], None, false);
    let calls: Vec<_> = GlesReader::new(&writer.snappy(1 << 20)[..], Limits::DEFAULT).unwrap().collect();
    assert_eq!(calls.len(), 2, "the iterator ends after the error");
    assert_eq!(calls[0].as_ref().unwrap().command, Command::Flush);
    match &calls[1] {
        Err(Error::Decode(e)) => {
            assert_eq!((e.call, e.function.as_str()), (1, "glFrobnicate"));
            assert!(matches!(e.kind, DecodeErrorKind::Unknown));
            let message = e.to_string();
            assert!(message.contains("call 1") && message.contains("glFrobnicate"), "{message}");
        }
        other => panic!("expected a decode error, got {other:?}"),
    }
}

#[test]
fn fake_calls_decode_and_are_flagged() {
    let mut writer = Writer::new(6);
    let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(800)), ("height", W::UInt(600))];
    writer.call("glViewport", &viewport, None, true);
    writer.call("glViewport", &viewport, None, false);
    let calls = decode(&writer).unwrap();
    let expected = Command::Viewport { x: 0, y: 0, width: 800, height: 600 };
    assert_eq!((calls[0].fake, &calls[0].command), (true, &expected));
    assert_eq!((calls[1].fake, &calls[1].command), (false, &expected));
}

/// Binds buffer `name` to `target` and gives it `size` bytes.
fn buffer(writer: &mut Writer, name: u64, target: (&'static str, GlEnum), size: u64) {
    writer.call("glBindBuffer", &[("target", gl_enum(target.0, target.1)), ("buffer", W::UInt(name))], None, false);
    writer.call(
        "glBufferData",
        &[
            ("target", gl_enum(target.0, target.1)),
            ("size", W::UInt(size)),
            ("data", W::Null),
            ("usage", gl_enum("GL_DYNAMIC_DRAW", 0x88e8)),
        ],
        None,
        false,
    );
}

fn memcpy(writer: &mut Writer, dest: u64, bytes: Vec<u8>) {
    let n = bytes.len() as u64;
    writer.call("memcpy", &[("dest", W::Pointer(dest)), ("src", W::Blob(bytes)), ("n", W::UInt(n))], None, true);
}

const ARRAY: (&str, GlEnum) = ("GL_ARRAY_BUFFER", GL_ARRAY_BUFFER);
const ELEMENTS: (&str, GlEnum) = ("GL_ELEMENT_ARRAY_BUFFER", GL_ELEMENT_ARRAY_BUFFER);

#[test]
fn writes_through_a_mapped_range_land_at_the_range_offset() {
    let mut writer = Writer::new(6);
    buffer(&mut writer, 7, ARRAY, 100);
    writer.call(
        "glMapBufferRange",
        &[
            ("target", gl_enum(ARRAY.0, ARRAY.1)),
            ("offset", W::UInt(16)),
            ("length", W::UInt(64)),
            ("access", W::Bitmask { id: 1, flags: vec![("GL_MAP_WRITE_BIT", 2)], value: 2 }),
        ],
        Some(W::Pointer(0x1000)),
        false,
    );
    memcpy(&mut writer, 0x1010, vec![1, 2, 3, 4, 5, 6, 7, 8]);
    writer.call("glUnmapBuffer", &[("target", gl_enum(ARRAY.0, ARRAY.1))], Some(W::Bool(true)), false);
    let commands = commands(&writer);
    assert_eq!(
        commands[2],
        Command::MapBuffer {
            target: GL_ARRAY_BUFFER,
            buffer: 7,
            offset: 16,
            length: Some(64),
            access: 2,
            pointer: 0x1000
        }
    );
    // 0x1010 - 0x1000 into a range that starts at 16.
    assert_eq!(commands[3], Command::BufferWrite { buffer: 7, offset: 32, data: vec![1, 2, 3, 4, 5, 6, 7, 8] });
    assert_eq!(commands[4], Command::UnmapBuffer { target: GL_ARRAY_BUFFER, buffer: 7 });
}

#[test]
fn element_buffer_maps_follow_the_vertex_array_bound() {
    let mut writer = Writer::new(6);
    writer.call("glBindVertexArray", &[("array", W::UInt(1))], None, false);
    buffer(&mut writer, 3, ELEMENTS, 12);
    writer.call("glBindVertexArray", &[("array", W::UInt(2))], None, false);
    buffer(&mut writer, 4, ELEMENTS, 12);
    writer.call("glBindVertexArray", &[("array", W::UInt(1))], None, false);
    writer.call(
        "glMapBufferOES",
        &[("target", gl_enum(ELEMENTS.0, ELEMENTS.1)), ("access", gl_enum("GL_WRITE_ONLY", GL_WRITE_ONLY_OES))],
        Some(W::Pointer(0x2000)),
        false,
    );
    memcpy(&mut writer, 0x2004, vec![9; 8]);
    let commands = commands(&writer);
    assert_eq!(commands.last().unwrap(), &Command::BufferWrite { buffer: 3, offset: 4, data: vec![9; 8] });
}

#[test]
fn writes_outside_any_mapping_are_errors() {
    let mut writer = Writer::new(6);
    buffer(&mut writer, 1, ARRAY, 16);
    writer.call(
        "glMapBufferOES",
        &[("target", gl_enum(ARRAY.0, ARRAY.1)), ("access", gl_enum("GL_WRITE_ONLY", GL_WRITE_ONLY_OES))],
        Some(W::Pointer(0x1000)),
        false,
    );
    // 8 bytes at 12: past the 16-byte buffer.
    memcpy(&mut writer, 0x100c, vec![0; 8]);
    match decode(&writer) {
        Err(Error::Decode(e)) => {
            assert_eq!((e.call, e.function.as_str()), (3, "memcpy"));
            assert!(matches!(e.kind, DecodeErrorKind::UnmappedWrite { dest: 0x100c, size: 8 }), "{e}");
        }
        other => panic!("expected an error, got {other:?}"),
    }

    let mut writer = Writer::new(6);
    memcpy(&mut writer, 0x1000, vec![0; 4]);
    assert!(
        matches!(decode(&writer), Err(Error::Decode(e)) if matches!(e.kind, DecodeErrorKind::UnmappedWrite { .. }))
    );
}

#[test]
fn vertex_attributes_from_client_memory_and_from_buffers() {
    let mut writer = Writer::new(6);
    let attrib = |pointer: W| {
        [
            ("index", W::UInt(1)),
            ("size", W::UInt(3)),
            ("type", gl_enum("GL_FLOAT", GL_FLOAT)),
            ("normalized", gl_enum("GL_FALSE", 0)),
            ("stride", W::UInt(12)),
            ("pointer", pointer),
        ]
    };
    writer.call("glVertexAttribPointer", &attrib(W::Blob(vec![0; 36])), None, true);
    writer.call("glVertexAttribPointer", &attrib(W::Pointer(24)), None, false);
    writer.call("glVertexAttribPointer", &attrib(W::Null), None, false);
    let pointers: Vec<Memory> = commands(&writer)
        .into_iter()
        .map(|c| match c {
            Command::VertexAttribPointer {
                index: 1,
                size: 3,
                kind: GL_FLOAT,
                normalized: false,
                stride: 12,
                pointer,
                integer: false,
            } => pointer,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(pointers, [Memory::Client(vec![0; 36]), Memory::Offset(24), Memory::Null]);
}

#[test]
fn every_uniform_form_decodes() {
    let mut writer = Writer::new(6);
    writer.call(
        "glUniform3f",
        &[("location", W::UInt(2)), ("v0", W::Float(1.0)), ("v1", W::Float(2.0)), ("v2", W::Float(3.0))],
        None,
        false,
    );
    writer.call(
        "glUniform2iv",
        &[
            ("location", W::UInt(3)),
            ("count", W::UInt(2)),
            ("value", W::Array(vec![W::UInt(1), W::Neg(2), W::UInt(3), W::UInt(4)])),
        ],
        None,
        false,
    );
    writer.call(
        "glUniformMatrix2x3fv",
        &[
            ("location", W::Neg(1)),
            ("count", W::UInt(1)),
            ("transpose", gl_enum("GL_TRUE", 1)),
            ("value", W::Array((0..6).map(|i| W::Float(i as f32)).collect())),
        ],
        None,
        false,
    );
    writer.call("glUniform1ui", &[("location", W::UInt(4)), ("v0", W::UInt(9))], None, false);
    let commands = commands(&writer);
    assert_eq!(
        commands,
        [
            Command::Uniform { location: 2, value: UniformValue::Float { components: 3, values: vec![1.0, 2.0, 3.0] } },
            Command::Uniform { location: 3, value: UniformValue::Int { components: 2, values: vec![1, -2, 3, 4] } },
            Command::Uniform {
                location: -1,
                value: UniformValue::Matrix {
                    columns: 2,
                    rows: 3,
                    transpose: true,
                    values: vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
                }
            },
            Command::Uniform { location: 4, value: UniformValue::UInt { components: 1, values: vec![9] } },
        ]
    );
}

#[test]
fn a_uniform_array_of_the_wrong_length_is_an_error() {
    let mut writer = Writer::new(6);
    writer.call(
        "glUniform4fv",
        &[("location", W::UInt(0)), ("count", W::UInt(2)), ("value", W::Array(vec![W::Float(0.0); 7]))],
        None,
        false,
    );
    match decode(&writer) {
        Err(Error::Decode(e)) => assert!(matches!(e.kind, DecodeErrorKind::Count { expected: 8, found: 7, .. }), "{e}"),
        other => panic!("expected an error, got {other:?}"),
    }
}

#[test]
fn a_wrong_argument_type_names_the_argument() {
    let mut writer = Writer::new(6);
    writer.call("glEnable", &[("cap", W::Str("GL_BLEND"))], None, false);
    match decode(&writer) {
        Err(Error::Decode(e)) => {
            let message = e.to_string();
            assert!(message.contains("`cap`") && message.contains("glEnable"), "{message}");
        }
        other => panic!("expected an error, got {other:?}"),
    }
}

#[test]
fn locations_keep_their_recorded_return_values() {
    let mut writer = Writer::new(6);
    writer.call(
        "glGetUniformLocation",
        &[("program", W::UInt(3)), ("name", W::Str("Viewport"))],
        Some(W::UInt(5)),
        false,
    );
    writer.call(
        "glGetAttribLocation",
        &[("program", W::UInt(3)), ("name", W::Str("position"))],
        Some(W::Neg(1)),
        false,
    );
    writer.call("glGetError", &[], Some(gl_enum("GL_NO_ERROR", 0)), false);
    let commands = commands(&writer);
    assert_eq!(commands[0], Command::UniformLocation { program: 3, name: "Viewport".into(), location: 5 });
    assert_eq!(commands[1], Command::AttribLocation { program: 3, name: "position".into(), location: -1 });
    assert!(matches!(commands[2], Command::Ignored { function: "glGetError", .. }));
}

#[test]
fn the_ignore_list_has_each_function_once_with_a_reason() {
    let mut names: Vec<&str> = IGNORED.iter().map(|(name, _)| *name).collect();
    names.sort();
    let before = names.len();
    names.dedup();
    assert_eq!(names.len(), before, "a function is listed twice");
    for (name, reason) in IGNORED {
        assert!(!reason.is_empty(), "{name}");
        assert!(name.starts_with("gl") || name.starts_with("egl"), "{name}");
    }
    for kept in
        ["glGetUniformLocation", "glGetAttribLocation", "glGetUniformBlockIndex", "glReadPixels", "glGetQueryObjectuiv"]
    {
        assert!(!names.contains(&kept), "{kept} must decode to its own command");
    }
}

#[test]
fn single_and_separate_forms_share_a_command() {
    let mut writer = Writer::new(6);
    writer.call("glBlendFunc", &[("sfactor", gl_enum("GL_ONE", 1)), ("dfactor", gl_enum("GL_ZERO", 0))], None, false);
    writer.call(
        "glStencilFunc",
        &[("func", gl_enum("GL_EQUAL", 0x0202)), ("ref", W::UInt(1)), ("mask", W::UInt(0xff))],
        None,
        false,
    );
    writer.call(
        "glDrawElementsInstanced",
        &[
            ("mode", gl_enum("GL_TRIANGLES", GL_TRIANGLES)),
            ("count", W::UInt(6)),
            ("type", gl_enum("GL_UNSIGNED_SHORT", GL_UNSIGNED_SHORT)),
            ("indices", W::Blob(vec![0, 0, 1, 0, 2, 0, 0, 0, 2, 0, 3, 0])),
            ("instancecount", W::UInt(4)),
        ],
        None,
        false,
    );
    let commands = commands(&writer);
    assert_eq!(commands[0], Command::BlendFunc { src_rgb: 1, dst_rgb: 0, src_alpha: 1, dst_alpha: 0 });
    assert_eq!(commands[1], Command::StencilFunc { face: GL_FRONT_AND_BACK, func: 0x0202, reference: 1, mask: 0xff });
    assert!(matches!(
        &commands[2],
        Command::DrawElements { mode: GL_TRIANGLES, count: 6, kind: GL_UNSIGNED_SHORT, indices: Memory::Client(bytes), instance_count: 4, range: None, base_vertex: 0 } if bytes.len() == 12
    ));
}

/// Every OpenGL ES 2.0 entry point (Khronos `gl2.h`).
pub const GLES2: &[&str] = &[
    "glActiveTexture",
    "glAttachShader",
    "glBindAttribLocation",
    "glBindBuffer",
    "glBindFramebuffer",
    "glBindRenderbuffer",
    "glBindTexture",
    "glBlendColor",
    "glBlendEquation",
    "glBlendEquationSeparate",
    "glBlendFunc",
    "glBlendFuncSeparate",
    "glBufferData",
    "glBufferSubData",
    "glCheckFramebufferStatus",
    "glClear",
    "glClearColor",
    "glClearDepthf",
    "glClearStencil",
    "glColorMask",
    "glCompileShader",
    "glCompressedTexImage2D",
    "glCompressedTexSubImage2D",
    "glCopyTexImage2D",
    "glCopyTexSubImage2D",
    "glCreateProgram",
    "glCreateShader",
    "glCullFace",
    "glDeleteBuffers",
    "glDeleteFramebuffers",
    "glDeleteProgram",
    "glDeleteRenderbuffers",
    "glDeleteShader",
    "glDeleteTextures",
    "glDepthFunc",
    "glDepthMask",
    "glDepthRangef",
    "glDetachShader",
    "glDisable",
    "glDisableVertexAttribArray",
    "glDrawArrays",
    "glDrawElements",
    "glEnable",
    "glEnableVertexAttribArray",
    "glFinish",
    "glFlush",
    "glFramebufferRenderbuffer",
    "glFramebufferTexture2D",
    "glFrontFace",
    "glGenBuffers",
    "glGenerateMipmap",
    "glGenFramebuffers",
    "glGenRenderbuffers",
    "glGenTextures",
    "glGetActiveAttrib",
    "glGetActiveUniform",
    "glGetAttachedShaders",
    "glGetAttribLocation",
    "glGetBooleanv",
    "glGetBufferParameteriv",
    "glGetError",
    "glGetFloatv",
    "glGetFramebufferAttachmentParameteriv",
    "glGetIntegerv",
    "glGetProgramiv",
    "glGetProgramInfoLog",
    "glGetRenderbufferParameteriv",
    "glGetShaderiv",
    "glGetShaderInfoLog",
    "glGetShaderPrecisionFormat",
    "glGetShaderSource",
    "glGetString",
    "glGetTexParameterfv",
    "glGetTexParameteriv",
    "glGetUniformfv",
    "glGetUniformiv",
    "glGetUniformLocation",
    "glGetVertexAttribfv",
    "glGetVertexAttribiv",
    "glGetVertexAttribPointerv",
    "glHint",
    "glIsBuffer",
    "glIsEnabled",
    "glIsFramebuffer",
    "glIsProgram",
    "glIsRenderbuffer",
    "glIsShader",
    "glIsTexture",
    "glLineWidth",
    "glLinkProgram",
    "glPixelStorei",
    "glPolygonOffset",
    "glReadPixels",
    "glReleaseShaderCompiler",
    "glRenderbufferStorage",
    "glSampleCoverage",
    "glScissor",
    "glShaderBinary",
    "glShaderSource",
    "glStencilFunc",
    "glStencilFuncSeparate",
    "glStencilMask",
    "glStencilMaskSeparate",
    "glStencilOp",
    "glStencilOpSeparate",
    "glTexImage2D",
    "glTexParameterf",
    "glTexParameterfv",
    "glTexParameteri",
    "glTexParameteriv",
    "glTexSubImage2D",
    "glUniform1f",
    "glUniform1fv",
    "glUniform1i",
    "glUniform1iv",
    "glUniform2f",
    "glUniform2fv",
    "glUniform2i",
    "glUniform2iv",
    "glUniform3f",
    "glUniform3fv",
    "glUniform3i",
    "glUniform3iv",
    "glUniform4f",
    "glUniform4fv",
    "glUniform4i",
    "glUniform4iv",
    "glUniformMatrix2fv",
    "glUniformMatrix3fv",
    "glUniformMatrix4fv",
    "glUseProgram",
    "glValidateProgram",
    "glVertexAttrib1f",
    "glVertexAttrib1fv",
    "glVertexAttrib2f",
    "glVertexAttrib2fv",
    "glVertexAttrib3f",
    "glVertexAttrib3fv",
    "glVertexAttrib4f",
    "glVertexAttrib4fv",
    "glVertexAttribPointer",
    "glViewport",
];

/// The GLES 3.0, extension and EGL calls the typed layer promises.
pub const MORE: &[&str] = &[
    "glGenVertexArrays",
    "glBindVertexArray",
    "glDeleteVertexArrays",
    "glGenVertexArraysOES",
    "glBindVertexArrayOES",
    "glDeleteVertexArraysOES",
    "glInvalidateFramebuffer",
    "glInvalidateSubFramebuffer",
    "glDiscardFramebufferEXT",
    "glBlitFramebuffer",
    "glDrawBuffers",
    "glDrawBuffersEXT",
    "glReadBuffer",
    "glDrawArraysInstanced",
    "glDrawElementsInstanced",
    "glDrawRangeElements",
    "glVertexAttribDivisor",
    "glVertexAttribIPointer",
    "glBindBufferBase",
    "glBindBufferRange",
    "glGetUniformBlockIndex",
    "glUniformBlockBinding",
    "glMapBufferRange",
    "glUnmapBuffer",
    "glFlushMappedBufferRange",
    "glMapBufferOES",
    "glUnmapBufferOES",
    "memcpy",
    "glCopyBufferSubData",
    "glTexStorage2D",
    "glGenSamplers",
    "glBindSampler",
    "glSamplerParameteri",
    "glDeleteSamplers",
    "glClearBufferfv",
    "glClearBufferiv",
    "glClearBufferuiv",
    "glClearBufferfi",
    "glGenQueries",
    "glBeginQuery",
    "glEndQuery",
    "glGetQueryObjectuiv",
    "glDeleteQueries",
    "glRenderbufferStorageMultisample",
    "glRenderbufferStorageMultisampleEXT",
    "glFramebufferTexture2DMultisampleEXT",
    "glUniform2ui",
    "glUniform4uiv",
    "glUniformMatrix3x4fv",
    "glStartTilingQCOM",
    "glEndTilingQCOM",
    "eglSwapBuffers",
    "eglSwapBuffersWithDamageKHR",
    "eglCreateContext",
    "eglDestroyContext",
    "eglMakeCurrent",
    "eglCreateWindowSurface",
    "eglCreatePbufferSurface",
    "eglDestroySurface",
    "eglSurfaceAttrib",
];

#[test]
fn every_gles2_call_and_the_promised_others_are_known() {
    use std::sync::Arc;
    use tiler_apitrace::wire::{Call, CallFlags, FunctionSig};
    for name in GLES2.iter().chain(MORE) {
        // No arguments: a known call fails on its first missing argument (or decodes, when it
        // has none); only an unknown one says so.
        let call = Call {
            number: 9,
            thread: 0,
            sig: Arc::new(FunctionSig { id: 0, name: name.to_string(), arg_names: vec![] }),
            args: vec![],
            ret: None,
            backtrace: vec![],
            flags: CallFlags::default(),
        };
        if let Err(e) = tiler_apitrace::Decoder::new().decode(call) {
            assert!(!matches!(e.kind, DecodeErrorKind::Unknown), "{name} is unknown");
        }
    }
    assert_eq!(GLES2.len(), 142);
}

#[test]
fn fences_and_client_waits_decode_to_commands_and_gpu_waits_are_ignored() {
    let mut writer = Writer::new(6);
    writer.call(
        "glFenceSync",
        &[("condition", gl_enum("GL_SYNC_GPU_COMMANDS_COMPLETE", 0x9117)), ("flags", W::UInt(0))],
        Some(W::UInt(0x5555_0000)),
        false,
    );
    writer.call(
        "glClientWaitSync",
        &[("sync", W::UInt(0x5555_0000)), ("flags", W::UInt(1)), ("timeout", W::UInt(1_000_000_000))],
        Some(gl_enum("GL_CONDITION_SATISFIED", 0x911c)),
        false,
    );
    writer.call(
        "glWaitSync",
        &[("sync", W::UInt(0x5555_0000)), ("flags", W::UInt(0)), ("timeout", W::UInt(u64::MAX))],
        None,
        false,
    );
    writer.call("glDeleteSync", &[("sync", W::UInt(0x5555_0000))], None, false);
    let commands = commands(&writer);
    assert_eq!(commands[0], Command::FenceSync { sync: 0x5555_0000 });
    assert_eq!(commands[1], Command::ClientWaitSync { sync: 0x5555_0000, flags: 1, timeout: 1_000_000_000 });
    assert!(matches!(commands[2], Command::Ignored { function: "glWaitSync", .. }));
    assert_eq!(commands[3], Command::DeleteSync { sync: 0x5555_0000 });
}

#[test]
fn calls_of_unmodelled_features_and_of_desktop_gl_say_so() {
    for (function, says) in [
        ("glProgramBinary", "program binaries"),
        ("glCompressedTexImage3D", "compressed 3-D and 2-D array textures"),
        ("glCreateProgramObjectARB", "desktop OpenGL"),
        ("glBegin", "desktop OpenGL"),
    ] {
        let mut writer = Writer::new(6);
        writer.call(function, &[("mode", gl_enum("GL_POINTS", 0))], None, false);
        match decode(&writer) {
            Err(Error::Decode(e)) => {
                let message = e.to_string();
                assert!(message.contains(function) && message.contains(says), "{message}");
            }
            other => panic!("{function}: expected an error, got {other:?}"),
        }
    }
    // Other unknown calls keep the general message.
    let mut writer = Writer::new(6);
    writer.call("glFrobnicate", &[], None, false);
    assert!(matches!(decode(&writer), Err(Error::Decode(e)) if e.to_string().contains("ignore list")));
}
