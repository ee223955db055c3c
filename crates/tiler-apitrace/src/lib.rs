//! Reads apitrace captures of OpenGL ES / EGL applications, one call at a time.
//!
//! Two layers:
//!
//! - [`wire`]: the binary format — container, header, events, signatures, values — into
//!   [`Call`]s carrying untyped [`Value`]s, streamed by [`TraceReader`] with bounded memory.
//! - [`gles`]: each call decoded into a [`Command`] — every OpenGL ES 2.0 call that draws or
//!   changes state, the GLES 3.0 calls applications use most, their OES/EXT variants, and EGL —
//!   streamed by [`GlesReader`]; writes through mapped buffers resolved to
//!   [`Command::BufferWrite`].
//!
//! This crate knows nothing of tiler's other crates; a later step maps its output onto
//! tiler-gl's GL-style context.
//!
//! # The format as implemented
//!
//! Written from apitrace's `docs/FORMAT.markdown`, `lib/trace/trace_parser.cpp`,
//! `trace_format.hpp` and `trace_file_snappy.cpp`, and checked call by call against
//! `apitrace dump` on the shared glmark2 captures.
//!
//! **Container.** Snappy: the bytes `at`, then chunks, each a little-endian `u32` compressed
//! length and one raw snappy block (apitrace writes at most 1 MiB uncompressed per block; values
//! continue across blocks). Gzip (`1f 8b`): one gzip stream. zstd (`28 b5 2f fd`) is named and
//! refused; brotli has no magic, so anything else is refused as an unknown container that may be
//! brotli. `apitrace repack` rewrites either as snappy.
//!
//! **Integers** are unsigned LEB128 varints (at most 64 bits; longer is an error). Floats and
//! doubles are 4 and 8 little-endian bytes. A string is a varint length and its bytes.
//!
//! **Header.** The format version (0–6 accepted). From version 6: a semantic version (not above
//! the format version), then property name/value string pairs ended by an empty name.
//!
//! **Events.** `0x00` enters a call: a thread number (version 4 on), a function signature, then
//! call details. Calls are numbered from 0 in enter order. `0x01` leaves one: its number, then
//! details. Calls may leave out of order; [`TraceReader`] yields each when it leaves, and at the
//! end of the stream yields calls that never left with [`CallFlags::incomplete`] set. Leaving
//! a call that is not pending is an error (apitrace skips it; that only happens when seeking).
//!
//! **Call details.** `0` ends them; `1` an argument (index, value; the index must be below the
//! signature's argument count); `2` the return value; `3` the thread number (before version
//! 4); `4` a backtrace (a count, then frames); `5` flags (bit 0: a fake call apitrace
//! synthesised — replay applies it).
//!
//! **Signatures** (function, enum, bitmask, struct, backtrace frame) are an id, followed by the
//! definition the first time the id occurs, and by nothing afterwards. Function: name, count,
//! argument names. Enum (version 3 on): count, then name and tagged signed integer pairs; before
//! version 3, one name and its value. Bitmask: count, then name and varint pairs. Struct: name,
//! count, member names. Frame: details `1` module, `2` function, `3` file (strings), `4` line,
//! `5` offset (varints), ended by `0`.
//!
//! **Values** by tag: `0x00` null, `0x01` false, `0x02` true, `0x03` negative integer (its
//! magnitude), `0x04` unsigned integer, `0x05` float, `0x06` double, `0x07` string, `0x08`
//! blob, `0x09` enum (signature, then a tagged `0x03`/`0x04` integer; before version 3 the value
//! is the signature's), `0x0a` bitmask (signature, then a raw varint), `0x0b` array (count,
//! values), `0x0c` struct (signature, one value per member), `0x0d` opaque pointer (varint),
//! `0x0e` repr (human value, machine value), `0x0f` wide string (count, varint characters).
//!
//! **Limits.** Every count and length is checked against [`Limits`] before memory is reserved;
//! the bytes held by pending calls, the signatures, the nesting depth and the stream length are
//! bounded too. Every error is a [`ReadError`] naming the byte of the uncompressed stream, the
//! snappy chunk (file offset and offset inside it) and the call being read.

//! # The typed layer's ignore list
//!
//! These calls change nothing tiler models; they decode to [`Command::Ignored`] carrying the
//! reason ([`gles::IGNORED`] is the list in code). Any call neither decoded nor listed is an
//! error naming its number and function.
//!
//! - *Reads state back* (`glGet*`, `glIs*`, `glCheckFramebufferStatus`, `eglQuery*`,
//!   `eglGetConfigAttrib`): glGetActiveAttrib, glGetActiveUniform, glGetActiveUniformBlockiv,
//!   glGetActiveUniformBlockName, glGetActiveUniformsiv, glGetAttachedShaders, glGetBooleanv,
//!   glGetBufferParameteriv, glGetBufferParameteri64v, glGetBufferPointerv,
//!   glGetBufferPointervOES, glGetFloatv, glGetFragDataLocation,
//!   glGetFramebufferAttachmentParameteriv, glGetInteger64v, glGetIntegeri_v,
//!   glGetInteger64i_v, glGetIntegerv, glGetInternalformativ, glGetProgramInfoLog,
//!   glGetProgramiv, glGetQueryiv, glGetQueryivEXT, glGetRenderbufferParameteriv,
//!   glGetSamplerParameterfv, glGetSamplerParameteriv, glGetShaderInfoLog,
//!   glGetShaderPrecisionFormat, glGetShaderSource, glGetShaderiv, glGetString, glGetStringi,
//!   glGetTexParameterfv, glGetTexParameteriv, glGetTexLevelParameterfv,
//!   glGetTexLevelParameteriv, glGetUniformIndices, glGetUniformfv,
//!   glGetUniformiv, glGetUniformuiv, glGetVertexAttribPointerv, glGetVertexAttribfv,
//!   glGetVertexAttribiv, glCheckFramebufferStatus, glIsBuffer, glIsEnabled, glIsFramebuffer,
//!   glIsProgram, glIsQuery, glIsQueryEXT, glIsRenderbuffer, glIsSampler, glIsShader, glIsTexture,
//!   glIsVertexArray, glIsVertexArrayOES, eglQueryString, eglQueryContext, eglQuerySurface,
//!   eglQueryAPI, eglGetConfigAttrib.
//! - *Reads the error flag*: glGetError, eglGetError.
//! - *EGL display and config setup* — the surface and context calls carry what rendering
//!   needs: eglGetConfigs, eglChooseConfig, eglGetDisplay, eglGetPlatformDisplay,
//!   eglGetPlatformDisplayEXT, eglInitialize, eglTerminate, eglBindAPI, eglReleaseThread.
//! - *Reads which context or surface is current* (`eglMakeCurrent` sets it):
//!   eglGetCurrentContext, eglGetCurrentDisplay, eglGetCurrentSurface.
//! - *Looks up a function pointer*: eglGetProcAddress.
//! - *Paces presentation* — the image and its traffic are the same: eglSwapInterval.
//! - *Sets only the validate status*, which only a query reads: glValidateProgram.
//! - *A hint to free compiler resources*: glReleaseShaderCompiler.
//! - *Debug labels, markers, callbacks*: glDebugMessageCallback (+KHR),
//!   glDebugMessageControl (+KHR), glDebugMessageInsert (+KHR), glInsertEventMarkerEXT,
//!   glObjectLabel (+KHR), glPopDebugGroup (+KHR), glPopGroupMarkerEXT, glPushDebugGroup (+KHR),
//!   glPushGroupMarkerEXT.
//! - *Sync objects* — a GPU-side wait changes nothing (one context's commands run in
//!   order), nor does a query of a sync object (`glFenceSync`, `glClientWaitSync` and
//!   `glDeleteSync` decode to commands: where the CPU waits is modelled): glWaitSync, glIsSync,
//!   glGetSynciv.
//!
//! Calls of a feature tiler does not model (compressed 3-D and array textures, program
//! binaries, compute) and desktop OpenGL calls fail with
//! [`DecodeErrorKind::NotModelled`](gles::DecodeErrorKind::NotModelled), which names the
//! feature.
//!
//! `glGetUniformLocation`, `glGetAttribLocation` and `glGetUniformBlockIndex` change nothing
//! either, but their recorded return values are the names later calls use, so they decode to
//! [`Command::UniformLocation`], [`Command::AttribLocation`] and
//! [`Command::UniformBlockIndex`]. `glGetQueryObjectuiv` (and `EXT_disjoint_timer_query`'s
//! `glGetQueryObject{i,ui,i64,ui64}vEXT`) and `glReadPixels` read back too, but make a tiler
//! render what is pending, so they decode to commands; so does `glQueryCounterEXT`, whose
//! query a later read waits for.

pub mod gles;
pub mod wire;

pub use gles::{Command, Decoder, Error, GlesCall, GlesReader, Memory};
pub use wire::{Call, CallFlags, Limits, ReadError, TraceReader, Value};
