//! The wire reader on generated captures: every value tag, event order, flags, versions,
//! containers, and errors that say where.

use tiler_apitrace::wire::{Compression, Limits, ReadError, ReadErrorKind, TraceReader, Value};

use crate::writer::{W, Writer, snappy_container};

fn read_all(bytes: &[u8]) -> Result<Vec<tiler_apitrace::Call>, ReadError> {
    read_all_with(bytes, Limits::DEFAULT)
}

fn read_all_with(bytes: &[u8], limits: Limits) -> Result<Vec<tiler_apitrace::Call>, ReadError> {
    TraceReader::new(bytes, limits)?.collect()
}

fn every_tag() -> Vec<(&'static str, W)> {
    let flags = vec![("NONE", 0), ("A", 1), ("B", 4)];
    vec![
        ("null", W::Null),
        ("no", W::Bool(false)),
        ("yes", W::Bool(true)),
        ("negative", W::Neg(1 << 40)),
        ("unsigned", W::UInt(u64::MAX)),
        ("float", W::Float(-2.5)),
        ("double", W::Double(1e300)),
        ("string", W::Str("void main() {}")),
        ("blob", W::Blob((0..=255).collect())),
        ("enum", W::Enum { id: 3, values: vec![("GL_TRIANGLES", 4), ("MINUS", -7)], value: -7 }),
        ("bitmask", W::Bitmask { id: 5, flags, value: 5 }),
        ("array", W::Array(vec![W::UInt(1), W::Neg(2), W::Array(vec![])])),
        (
            "struct",
            W::Struct { id: 9, name: "Point", members: vec!["x", "y"], values: vec![W::Float(1.0), W::UInt(2)] },
        ),
        ("pointer", W::Pointer(0x55cb_6ac8_b1c0)),
        ("repr", W::Repr(Box::new(W::Str("GL_ONE")), Box::new(W::UInt(1)))),
        ("wide", W::Wide(vec![b'h' as u32, 0x263a, 0xd800])),
    ]
}

#[test]
fn every_value_tag_reads_back() {
    let mut writer = Writer::new(6);
    writer.call("everything", &every_tag(), Some(W::Neg(3)), false);
    let calls = read_all(&writer.snappy(1 << 20)).unwrap();
    assert_eq!(calls.len(), 1);
    let call = &calls[0];
    assert_eq!(call.name(), "everything");
    assert_eq!(call.sig.arg_names.len(), 16);
    let arg = |i: usize| call.arg(i).unwrap();
    assert_eq!(arg(0), &Value::Null);
    assert_eq!(arg(1), &Value::Bool(false));
    assert_eq!(arg(2), &Value::Bool(true));
    assert_eq!(arg(3), &Value::SInt(-(1 << 40)));
    assert_eq!(arg(4), &Value::UInt(u64::MAX));
    assert_eq!(arg(5), &Value::Float(-2.5));
    assert_eq!(arg(6), &Value::Double(1e300));
    assert_eq!(arg(7).as_str(), Some("void main() {}"));
    assert_eq!(arg(8), &Value::Blob((0..=255).collect()));
    match arg(9) {
        Value::Enum { sig, value } => {
            assert_eq!(*value, -7);
            assert_eq!(sig.name_of(-7), Some("MINUS"));
            assert_eq!(sig.name_of(4), Some("GL_TRIANGLES"));
        }
        other => panic!("expected an enum, got {other:?}"),
    }
    assert_eq!(arg(10).to_string(), "A | B");
    assert_eq!(arg(11).to_string(), "{1, -2, {}}");
    assert_eq!(arg(12).to_string(), "{x = 1, y = 2}");
    assert_eq!(arg(13), &Value::Pointer(0x55cb_6ac8_b1c0));
    assert_eq!(arg(14).to_string(), "\"GL_ONE\"");
    assert_eq!(arg(14).as_u64(), Some(1));
    assert_eq!(arg(15).as_str(), Some("h\u{263a}\u{fffd}"));
    assert_eq!(call.ret, Some(Value::SInt(-3)));
    assert!(!call.flags.fake && !call.flags.incomplete);
}

#[test]
fn signatures_are_defined_once_and_referred_to_by_id() {
    let mut writer = Writer::new(6);
    let gl_enum = W::gl_enum("GL_DEPTH_TEST", 0x0b71);
    writer.call("glEnable", &[("cap", gl_enum.clone())], None, false);
    let length_after_first = writer.stream.len();
    writer.call("glEnable", &[("cap", gl_enum)], None, false);
    // The second call is only event, thread, signature id, argument, enum id and value.
    assert!(writer.stream.len() - length_after_first < 16);
    let calls = read_all(&writer.snappy(1 << 20)).unwrap();
    assert_eq!(calls.len(), 2);
    assert!(std::sync::Arc::ptr_eq(&calls[0].sig, &calls[1].sig));
    assert_eq!(calls[1].to_string(), "1 glEnable(cap = GL_DEPTH_TEST)");
}

#[test]
fn calls_leave_out_of_order_and_come_out_as_they_leave() {
    let mut writer = Writer::new(6);
    let first = writer.enter("glFinish", &[]);
    writer.end();
    let second = writer.enter("eglSwapBuffers", &["dpy"]);
    writer.arg(0, &W::Pointer(1));
    writer.end();
    writer.leave(second);
    writer.ret(&W::Bool(true));
    writer.end();
    writer.leave(first);
    writer.end();
    let calls = read_all(&writer.snappy(1 << 20)).unwrap();
    let order: Vec<(u64, &str)> = calls.iter().map(|c| (c.number, c.name())).collect();
    assert_eq!(order, [(1, "eglSwapBuffers"), (0, "glFinish")]);
    assert_eq!(calls[0].ret, Some(Value::Bool(true)));
}

#[test]
fn fake_calls_are_flagged_and_kept() {
    let mut writer = Writer::new(6);
    writer.call("glViewport", &[("x", W::UInt(0))], None, true);
    writer.call("glViewport", &[("x", W::UInt(0))], None, false);
    let calls = read_all(&writer.snappy(1 << 20)).unwrap();
    assert!(calls[0].flags.fake);
    assert_eq!(calls[0].flags.raw, 1);
    assert!(!calls[1].flags.fake);
    assert!(calls[0].to_string().ends_with("// fake"));
}

#[test]
fn a_call_that_never_leaves_comes_out_incomplete_at_the_end() {
    let mut writer = Writer::new(6);
    writer.call("glFlush", &[], None, false);
    writer.enter("glFinish", &[]);
    writer.end();
    let calls = read_all(&writer.snappy(1 << 20)).unwrap();
    assert_eq!(calls.len(), 2);
    assert!(!calls[0].flags.incomplete);
    assert!(calls[1].flags.incomplete);
    assert_eq!(calls[1].name(), "glFinish");
}

#[test]
fn backtraces_define_frames_once() {
    let mut writer = Writer::new(6);
    for _ in 0..2 {
        let number = writer.enter("glFlush", &[]);
        writer.byte(0x04);
        writer.uint(1);
        writer.uint(42);
        if number == 0 {
            writer.byte(0x01);
            writer.string(b"libapp.so");
            writer.byte(0x02);
            writer.string(b"draw_frame");
            writer.byte(0x03);
            writer.string(b"app.c");
            writer.byte(0x04);
            writer.uint(120);
            writer.byte(0x05);
            writer.uint(0x4400);
            writer.byte(0x00);
        }
        writer.end();
        writer.leave(number);
        writer.end();
    }
    let calls = read_all(&writer.snappy(1 << 20)).unwrap();
    for call in &calls {
        let frame = &call.backtrace[0];
        assert_eq!(frame.function.as_deref(), Some("draw_frame"));
        assert_eq!(frame.module.as_deref(), Some("libapp.so"));
        assert_eq!(frame.filename.as_deref(), Some("app.c"));
        assert_eq!((frame.line, frame.offset), (Some(120), Some(0x4400)));
    }
}

/// A little of everything, for the container and version tests.
fn sample(version: u64) -> Writer {
    let mut writer = Writer::new(version);
    writer.call("glClear", &[("mask", W::UInt(0x4100))], None, false);
    writer.call(
        "glBlendFunc",
        &[("sfactor", W::gl_enum("GL_ONE", 1)), ("dfactor", W::gl_enum("GL_ONE", 1))],
        None,
        false,
    );
    writer.call("glBufferData", &[("data", W::Blob((0..200u8).collect()))], None, false);
    writer.call("eglSwapBuffers", &[("dpy", W::Pointer(7))], Some(W::Bool(true)), false);
    writer
}

fn summary(calls: &[tiler_apitrace::Call]) -> Vec<String> {
    calls.iter().map(|c| c.to_string()).collect()
}

#[test]
fn values_split_across_chunks_read_the_same() {
    let writer = sample(6);
    let whole = read_all(&writer.snappy(1 << 20)).unwrap();
    for chunk_bytes in [1, 2, 3, 7, 64] {
        let split = read_all(&writer.snappy(chunk_bytes)).unwrap();
        assert_eq!(split, whole, "chunks of {chunk_bytes} bytes");
    }
    assert_eq!(whole.len(), 4);
}

#[test]
fn gzip_captures_read_like_snappy_ones() {
    let writer = sample(6);
    let gzip = writer.gzip();
    let reader = TraceReader::new(&gzip[..], Limits::DEFAULT).unwrap();
    assert_eq!(reader.header().compression, Compression::Gzip);
    let calls: Vec<_> = reader.collect::<Result<_, _>>().unwrap();
    assert_eq!(calls, read_all(&writer.snappy(1 << 20)).unwrap());
}

#[test]
fn every_version_up_to_6_reads() {
    let expected = summary(&read_all(&sample(6).snappy(1 << 20)).unwrap());
    for version in 0..=6 {
        let bytes = sample(version).snappy(1 << 20);
        let reader = TraceReader::new(&bytes[..], Limits::DEFAULT).unwrap();
        let header = reader.header().clone();
        assert_eq!(header.version, version);
        assert_eq!(header.semantic_version, version);
        let properties = if version >= 6 { vec![("process.name".to_string(), "test".to_string())] } else { vec![] };
        assert_eq!(header.properties, properties);
        let calls: Vec<_> = reader.collect::<Result<_, _>>().unwrap();
        assert_eq!(summary(&calls), expected, "version {version}");
    }
}

#[test]
fn version_3_and_older_take_the_thread_as_a_call_detail() {
    let mut writer = Writer::new(3);
    let number = writer.enter("glFlush", &[]);
    writer.byte(0x03);
    writer.uint(5);
    writer.end();
    writer.leave(number);
    writer.end();
    let calls = read_all(&writer.snappy(1 << 20)).unwrap();
    assert_eq!(calls[0].thread, 5);
}

fn error_of(bytes: &[u8]) -> ReadError {
    error_with(bytes, Limits::DEFAULT)
}

fn error_with(bytes: &[u8], limits: Limits) -> ReadError {
    match read_all_with(bytes, limits) {
        Ok(calls) => panic!("expected an error, read {} calls", calls.len()),
        Err(e) => e,
    }
}

#[test]
fn newer_versions_are_refused() {
    let error = error_of(&Writer::new(7).snappy(64));
    assert!(matches!(error.kind, ReadErrorKind::UnsupportedVersion(7)), "{error}");
}

#[test]
fn unknown_and_unsupported_containers_are_named() {
    let zstd = [0x28, 0xb5, 0x2f, 0xfd, 0, 0];
    let error = error_of(&zstd);
    assert!(matches!(error.kind, ReadErrorKind::UnsupportedCompression("zstd")), "{error}");
    assert!(error.to_string().contains("zstd"));
    let error = error_of(b"{\"frames\": []}");
    assert!(matches!(error.kind, ReadErrorKind::UnknownContainer(_)), "{error}");
    assert!(error.to_string().contains("brotli"));
    assert!(matches!(error_of(b"a").kind, ReadErrorKind::Empty));
}

#[test]
fn an_unknown_value_tag_names_its_byte_and_call() {
    let mut writer = sample(6);
    let number = writer.enter("glFlush", &["x"]);
    writer.byte(0x01);
    writer.uint(0);
    let offset = writer.stream.len() as u64;
    writer.byte(0x10);
    let error = error_of(&writer.snappy(1 << 20));
    assert!(matches!(error.kind, ReadErrorKind::UnknownValueTag(0x10)), "{error}");
    // The tag's byte has been read: the error points just past it.
    assert_eq!(error.location.offset, offset + 1);
    assert_eq!(error.location.call, Some(number));
    let chunk = error.location.chunk.unwrap();
    assert_eq!((chunk.file_offset, chunk.offset_in_chunk), (2, offset + 1));
    assert!(error.to_string().starts_with(&format!("call {number}, stream byte {}", offset + 1)));
}

#[test]
fn truncation_is_an_error_at_the_end_of_the_stream() {
    let writer = sample(6);
    let full = writer.stream.len();
    // Cut inside the blob of call 2: a value that was being read.
    let blob_end = writer.stream.windows(3).position(|w| w == [197, 198, 199]).unwrap();
    let cut = &writer.stream[..blob_end];
    let error = error_of(&snappy_container(cut, 1 << 20));
    assert!(matches!(error.kind, ReadErrorKind::UnexpectedEnd("blob")), "{error}");
    assert_eq!(error.location.offset, cut.len() as u64);
    assert_eq!(error.location.call, Some(2));
    assert!(cut.len() < full);
}

#[test]
fn truncated_chunks_are_errors() {
    let bytes = sample(6).snappy(1 << 20);
    let error = error_of(&bytes[..bytes.len() - 1]);
    assert!(matches!(error.kind, ReadErrorKind::TruncatedChunk { .. }), "{error}");
    assert_eq!(error.location.chunk.unwrap().file_offset, 2);
    let error = error_of(&bytes[..4]);
    assert!(matches!(error.kind, ReadErrorKind::TruncatedChunkLength { got: 2 }), "{error}");
}

#[test]
fn varints_longer_than_64_bits_are_errors() {
    let mut stream = vec![6, 6, 0];
    stream.push(0x00); // enter
    stream.extend([0xff; 10]); // thread number: ten bytes of ones
    stream.push(0x01);
    let error = error_of(&snappy_container(&stream, 1 << 20));
    assert!(matches!(error.kind, ReadErrorKind::VarintOverflow(_)), "{error}");
    // Header 3 bytes, the enter byte, then the ten bytes; the tenth is where it overflows.
    assert_eq!(error.location.offset, 3 + 1 + 10);
}

#[test]
fn leaving_a_call_never_entered_is_an_error() {
    let mut writer = sample(6);
    writer.leave(99);
    writer.end();
    let error = error_of(&writer.snappy(1 << 20));
    assert!(matches!(error.kind, ReadErrorKind::LeaveUnknownCall(99)), "{error}");
}

#[test]
fn an_argument_index_past_the_signature_is_an_error() {
    let mut writer = Writer::new(6);
    writer.enter("glFlush", &[]);
    writer.arg(3, &W::Null);
    let error = error_of(&writer.snappy(1 << 20));
    assert!(
        matches!(&error.kind, ReadErrorKind::ArgumentIndex { index: 3, function, count: 0 } if function == "glFlush"),
        "{error}"
    );
}

#[test]
fn lengths_over_the_limits_are_refused_before_allocating() {
    // A blob that claims 2^60 bytes: refused from its length alone.
    let mut writer = Writer::new(6);
    writer.enter("glBufferData", &["data"]);
    writer.byte(0x01);
    writer.uint(0);
    writer.byte(0x08);
    writer.uint(1 << 60);
    let error = error_of(&writer.snappy(1 << 20));
    assert!(matches!(error.kind, ReadErrorKind::Limit { what: "blob", value, .. } if value == 1 << 60), "{error}");

    let mut writer = Writer::new(6);
    writer.call("f", &[("s", W::Str("0123456789abcdefghij"))], None, false);
    let limits = Limits { max_string_bytes: 19, ..Limits::DEFAULT };
    let error = error_with(&writer.snappy(1 << 20), limits);
    assert!(matches!(error.kind, ReadErrorKind::Limit { what: "string", value: 20, limit: 19 }), "{error}");

    let mut writer = Writer::new(6);
    let nested = (0..20).fold(W::Null, |inner, _| W::Array(vec![inner]));
    writer.call("f", &[("a", nested)], None, false);
    let error = error_with(&writer.snappy(1 << 20), Limits::SMALL);
    assert!(matches!(error.kind, ReadErrorKind::Limit { what: "value nesting depth", .. }), "{error}");

    let mut writer = Writer::new(6);
    for _ in 0..3 {
        writer.enter("glFlush", &[]);
        writer.end();
    }
    let limits = Limits { max_pending_calls: 2, ..Limits::DEFAULT };
    let error = error_with(&writer.snappy(1 << 20), limits);
    assert!(matches!(error.kind, ReadErrorKind::Limit { what: "calls entered and not left", .. }), "{error}");
    assert_eq!(error.location.call, Some(2));
}

#[test]
fn a_chunk_over_the_limit_is_refused() {
    let writer = sample(6);
    let limits = Limits { max_chunk_bytes: 16, ..Limits::DEFAULT };
    let error = error_with(&writer.snappy(1 << 20), limits);
    assert!(
        matches!(error.kind, ReadErrorKind::Limit { what: "uncompressed chunk bytes" | "compressed chunk bytes", .. }),
        "{error}"
    );
}

#[test]
fn held_bytes_are_bounded_across_pending_calls() {
    let mut writer = Writer::new(6);
    for _ in 0..4 {
        writer.enter("upload", &["data"]);
        writer.arg(0, &W::Blob(vec![0; 1000]));
        writer.end();
    }
    let limits = Limits { max_held_bytes: 3000, ..Limits::DEFAULT };
    let error = error_with(&writer.snappy(1 << 20), limits);
    assert!(matches!(error.kind, ReadErrorKind::Limit { what: "bytes held by pending calls", .. }), "{error}");
    assert_eq!(error.location.call, Some(2));
}
