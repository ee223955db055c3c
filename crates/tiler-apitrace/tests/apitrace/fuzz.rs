//! Property tests that run in CI: damaged captures never panic, stay within the small limits,
//! and fail with an error that says where.

use proptest::prelude::*;
use tiler_apitrace::wire::{Limits, ReadError, TraceReader};

use crate::writer::{W, Writer, snappy_container};

/// A small capture touching every tag, signatures reused, and a pair of calls leaving out of
/// order.
fn sample_stream() -> Vec<u8> {
    let mut writer = Writer::new(6);
    for frame in 0..3u64 {
        writer.call("glClearColor", &[("red", W::Float(0.5)), ("green", W::Double(0.25))], None, frame == 0);
        writer.call(
            "glShaderSource",
            &[
                ("shader", W::UInt(2)),
                ("count", W::UInt(1)),
                ("string", W::Array(vec![W::Str("void main() {}")])),
                ("length", W::Null),
            ],
            None,
            false,
        );
        writer.call("glEnable", &[("cap", W::gl_enum("GL_BLEND", 0x0be2))], None, false);
        writer.call(
            "glClear",
            &[("mask", W::Bitmask { id: 1, flags: vec![("GL_COLOR_BUFFER_BIT", 0x4000)], value: 0x4000 })],
            None,
            false,
        );
        writer.call(
            "memcpy",
            &[("dest", W::Pointer(0x1000)), ("src", W::Blob(vec![frame as u8; 40])), ("n", W::UInt(40))],
            None,
            true,
        );
        writer.call(
            "odd",
            &[
                ("neg", W::Neg(5)),
                ("repr", W::Repr(Box::new(W::Str("x")), Box::new(W::UInt(1)))),
                ("wide", W::Wide(vec![104, 105])),
                ("point", W::Struct { id: 2, name: "P", members: vec!["x"], values: vec![W::Bool(true)] }),
            ],
            Some(W::Null),
            false,
        );
        let a = writer.enter("glFinish", &[]);
        writer.end();
        let b = writer.enter("eglSwapBuffers", &["dpy"]);
        writer.arg(0, &W::Pointer(7));
        writer.end();
        writer.leave(b);
        writer.ret(&W::Bool(true));
        writer.end();
        writer.leave(a);
        writer.end();
    }
    writer.stream
}

/// Reads everything with the small limits; the calls read, or the error.
fn read(bytes: &[u8]) -> Result<usize, ReadError> {
    let mut count = 0;
    for call in TraceReader::new(bytes, Limits::SMALL)? {
        call?;
        count += 1;
    }
    Ok(count)
}

/// An error names a place inside what was read.
fn check_error(error: &ReadError, stream_len: u64) {
    assert!(
        error.location.offset <= stream_len,
        "offset {} past the stream's {stream_len} bytes: {error}",
        error.location.offset
    );
    assert!(!error.to_string().is_empty());
}

#[test]
fn the_sample_reads_whole() {
    let stream = sample_stream();
    assert_eq!(read(&snappy_container(&stream, 1 << 20)).unwrap(), 24);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn truncated_streams_fail_cleanly(cut in 0usize..4000, chunk in 1usize..300) {
        let stream = sample_stream();
        let cut = cut % (stream.len() + 1);
        match read(&snappy_container(&stream[..cut], chunk)) {
            Ok(count) => prop_assert!(count <= 24),
            Err(e) => check_error(&e, cut as u64),
        }
    }

    #[test]
    fn truncated_files_fail_cleanly(cut in 0usize..4000, chunk in 1usize..300) {
        let file = snappy_container(&sample_stream(), chunk);
        let cut = cut % (file.len() + 1);
        if let Err(e) = read(&file[..cut]) {
            check_error(&e, Limits::SMALL.max_stream_bytes);
        }
    }

    #[test]
    fn flipped_stream_bytes_fail_cleanly(
        flips in proptest::collection::vec((any::<usize>(), any::<u8>()), 1..8),
        chunk in 1usize..500,
    ) {
        let mut stream = sample_stream();
        let len = stream.len();
        for (at, byte) in flips {
            stream[at % len] ^= byte | 1;
        }
        if let Err(e) = read(&snappy_container(&stream, chunk)) {
            check_error(&e, len as u64);
        }
    }

    #[test]
    fn flipped_file_bytes_fail_cleanly(
        flips in proptest::collection::vec((any::<usize>(), any::<u8>()), 1..8),
    ) {
        let mut file = snappy_container(&sample_stream(), 256);
        let len = file.len();
        for (at, byte) in flips {
            file[at % len] ^= byte | 1;
        }
        if let Err(e) = read(&file) {
            check_error(&e, Limits::SMALL.max_stream_bytes);
        }
    }

    /// A valid header then anything: bad varints, unknown events, details, tags and
    /// signature ids never seen.
    #[test]
    fn random_events_fail_cleanly(tail in proptest::collection::vec(any::<u8>(), 0..600)) {
        let mut stream = Writer::new(6).stream;
        stream.extend(&tail);
        if let Err(e) = read(&snappy_container(&stream, 1 << 20)) {
            check_error(&e, stream.len() as u64);
        }
    }

    /// Events that start well (an enter of a fresh signature) and continue randomly, so the
    /// randomness reaches values and signatures.
    #[test]
    fn random_values_fail_cleanly(tail in proptest::collection::vec(any::<u8>(), 0..600)) {
        let mut writer = Writer::new(6);
        writer.enter("f", &["a", "b", "c"]);
        writer.byte(0x01);
        writer.uint(0);
        let mut stream = writer.stream;
        stream.extend(&tail);
        if let Err(e) = read(&snappy_container(&stream, 1 << 20)) {
            check_error(&e, stream.len() as u64);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// The typed layer over damaged captures: decoded calls or an error, never a panic.
    #[test]
    fn the_typed_layer_fails_cleanly(
        flips in proptest::collection::vec((any::<usize>(), any::<u8>()), 0..8),
    ) {
        let mut stream = gl_stream();
        let len = stream.len();
        for (at, byte) in flips {
            stream[at % len] ^= byte | 1;
        }
        let file = snappy_container(&stream, 128);
        let reader = tiler_apitrace::GlesReader::new(&file[..], Limits::SMALL);
        if let Ok(reader) = reader {
            for call in reader {
                if let Err(e) = call {
                    prop_assert!(!e.to_string().is_empty());
                }
            }
        }
    }
}

/// GL calls that decode: a buffer mapped and written, a shader, a draw, a swap.
fn gl_stream() -> Vec<u8> {
    let mut writer = Writer::new(6);
    let array = || W::gl_enum("GL_ARRAY_BUFFER", 0x8892);
    writer.call("glBindBuffer", &[("target", array()), ("buffer", W::UInt(1))], None, false);
    writer.call(
        "glBufferData",
        &[
            ("target", array()),
            ("size", W::UInt(64)),
            ("data", W::Null),
            ("usage", W::gl_enum("GL_STATIC_DRAW", 0x88e4)),
        ],
        None,
        false,
    );
    writer.call(
        "glMapBufferOES",
        &[("target", array()), ("access", W::gl_enum("GL_WRITE_ONLY", 0x88b9))],
        Some(W::Pointer(0x4000)),
        false,
    );
    writer.call(
        "memcpy",
        &[("dest", W::Pointer(0x4008)), ("src", W::Blob(vec![7; 16])), ("n", W::UInt(16))],
        None,
        true,
    );
    writer.call("glUnmapBufferOES", &[("target", array())], Some(W::gl_enum("GL_TRUE", 1)), false);
    writer.call(
        "glShaderSource",
        &[
            ("shader", W::UInt(2)),
            ("count", W::UInt(1)),
            ("string", W::Array(vec![W::Str("void main() {}")])),
            ("length", W::Null),
        ],
        None,
        false,
    );
    writer.call(
        "glDrawArrays",
        &[("mode", W::gl_enum("GL_TRIANGLES", 4)), ("first", W::UInt(0)), ("count", W::UInt(3))],
        None,
        false,
    );
    writer.call("eglSwapBuffers", &[("dpy", W::Pointer(1)), ("surface", W::Pointer(2))], Some(W::Bool(true)), false);
    writer.stream
}

#[test]
fn the_gl_sample_decodes_whole() {
    let file = snappy_container(&gl_stream(), 1 << 20);
    let calls: Vec<_> =
        tiler_apitrace::GlesReader::new(&file[..], Limits::SMALL).unwrap().collect::<Result<_, _>>().unwrap();
    assert_eq!(calls.len(), 8);
    assert_eq!(calls[3].command, tiler_apitrace::Command::BufferWrite { buffer: 1, offset: 8, data: vec![7; 16] });
}

/// A call whose signature has ten argument names, whatever it is (each function's signature
/// is defined by its first call).
fn emit(writer: &mut Writer, name: &str, args: &[W], ret: Option<W>) {
    const NAMES: [&str; 10] = ["a", "b", "c", "d", "e", "f", "g", "h", "i", "j"];
    let number = writer.enter(name, &NAMES);
    for (index, value) in args.iter().enumerate() {
        writer.arg(index as u64, value);
    }
    writer.end();
    writer.leave(number);
    if let Some(ret) = ret {
        writer.ret(&ret);
    }
    writer.end();
}

/// Any value of any kind, small.
fn any_value() -> impl Strategy<Value = W> {
    let leaf = prop_oneof![
        Just(W::Null),
        any::<bool>().prop_map(W::Bool),
        (0..=1u64 << 63).prop_map(W::Neg),
        any::<u64>().prop_map(W::UInt),
        (0u64..0x2000).prop_map(W::UInt),
        any::<f32>().prop_map(W::Float),
        Just(W::Str("void main() {}")),
        proptest::collection::vec(any::<u8>(), 0..64).prop_map(W::Blob),
        any::<u64>().prop_map(W::Pointer),
        (0x1000u64..0x1100).prop_map(W::Pointer),
        (0u32..0x9000).prop_map(|v| W::gl_enum("E", v as i64)),
    ];
    leaf.prop_recursive(2, 16, 8, |inner| proptest::collection::vec(inner, 0..8).prop_map(W::Array))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2048, failure_persistence: None, ..ProptestConfig::default() })]

    /// Known calls with arguments of any kind and value (wrong types, huge sizes, pointers
    /// near and far from a mapping): decoded or an error naming the call, never a panic.
    #[test]
    fn known_calls_with_any_arguments_fail_cleanly(
        calls in proptest::collection::vec(
            (0..crate::gles::GLES2.len() + crate::gles::MORE.len(),
             proptest::collection::vec(any_value(), 0..10),
             proptest::option::of(any_value())),
            1..12,
        ),
    ) {
        let mut writer = Writer::new(6);
        let all: Vec<&str> = crate::gles::GLES2.iter().chain(crate::gles::MORE).copied().collect();
        // A live mapping for memcpy to hit.
        let array = W::gl_enum("GL_ARRAY_BUFFER", 0x8892);
        emit(&mut writer, "glBindBuffer", &[array.clone(), W::UInt(1)], None);
        emit(
            &mut writer,
            "glMapBufferOES",
            &[array, W::gl_enum("GL_WRITE_ONLY", 0x88b9)],
            Some(W::Pointer(0x1000)),
        );
        for (which, args, ret) in calls {
            emit(&mut writer, all[which], &args, ret);
        }
        let file = snappy_container(&writer.stream, 1 << 20);
        for call in tiler_apitrace::GlesReader::new(&file[..], Limits::SMALL).unwrap() {
            match call {
                Ok(_) => {}
                Err(tiler_apitrace::Error::Decode(e)) => prop_assert!(e.to_string().contains(&e.function)),
                Err(e) => prop_assert!(false, "the wire is valid: {e}"),
            }
        }
    }
}
