//! Bulk data carried by calls (buffer contents, texels, client arrays), and the base64 codec
//! traces use to store it exactly (the `base64` crate, configured as traces write it).

use std::sync::Arc;

use base64::DecodeError;
use base64::Engine;
use base64::alphabet;
use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

/// Bytes shared cheaply between a call, its recording and the driver.
///
/// A `Vec` behind the `Arc` (not an `Arc<[u8]>`, which copies a `Vec` it is made from): a
/// converted upload goes into the call, and from the call into the device's image, without a
/// copy when nothing else holds it ([`Bytes::into_vec`]). A copy of a 1.9 MB texture was half a
/// millisecond of writing fresh pages.
#[derive(Clone, PartialEq, Eq, Default)]
pub struct Bytes(Arc<Vec<u8>>);

impl Bytes {
    pub fn new(bytes: impl Into<Vec<u8>>) -> Bytes {
        Bytes(Arc::new(bytes.into()))
    }

    /// The bytes as a `Vec`: taken when this is their only holder, copied otherwise.
    pub fn into_vec(self) -> Vec<u8> {
        Arc::try_unwrap(self.0).unwrap_or_else(|shared| shared.as_ref().clone())
    }

    /// Plain data (vertices, indices) as bytes, little-endian as on every target tiler runs on.
    pub fn from_slice<T: Copy + ToLeBytes>(values: &[T]) -> Bytes {
        let mut out = Vec::with_capacity(std::mem::size_of_val(values));
        for v in values {
            v.extend_le(&mut out);
        }
        Bytes::new(out)
    }

    pub fn as_slice(&self) -> &[u8] {
        &self.0
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl std::ops::Deref for Bytes {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        &self.0
    }
}

impl From<Vec<u8>> for Bytes {
    fn from(v: Vec<u8>) -> Bytes {
        Bytes::new(v)
    }
}

impl From<&[u8]> for Bytes {
    fn from(v: &[u8]) -> Bytes {
        Bytes::new(v)
    }
}

impl std::fmt::Debug for Bytes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Bytes({} bytes)", self.0.len())
    }
}

/// A trace stores bytes as `{"base64": "..."}`, one of the forms a data source may take.
impl Serialize for Bytes {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(1))?;
        map.serialize_entry("base64", &encode_base64(&self.0))?;
        map.end()
    }
}

/// Numbers that can be written as little-endian bytes.
pub trait ToLeBytes {
    fn extend_le(&self, out: &mut Vec<u8>);
}

macro_rules! to_le_bytes {
    ($($t:ty),*) => {$(
        impl ToLeBytes for $t {
            fn extend_le(&self, out: &mut Vec<u8>) {
                out.extend_from_slice(&self.to_le_bytes());
            }
        }
    )*};
}
to_le_bytes!(u8, u16, u32, i8, i16, i32, f32);

impl<T: ToLeBytes, const N: usize> ToLeBytes for [T; N] {
    fn extend_le(&self, out: &mut Vec<u8>) {
        for v in self {
            v.extend_le(out);
        }
    }
}

/// The traces' base64: the standard alphabet (RFC 4648 §4), `=` padding written; reading
/// takes it or leaves it, and ignores the unused low bits of a final partial group.
const TRACE_BASE64: GeneralPurpose = GeneralPurpose::new(
    &alphabet::STANDARD,
    GeneralPurposeConfig::new()
        .with_encode_padding(true)
        .with_decode_padding_mode(DecodePaddingMode::RequireNone)
        .with_decode_allow_trailing_bits(true),
);

/// Standard base64 (RFC 4648 §4) with `=` padding.
pub fn encode_base64(bytes: &[u8]) -> String {
    TRACE_BASE64.encode(bytes)
}

/// Decodes standard base64; padding is optional, whitespace is not allowed.
///
/// # Errors
/// A character outside the alphabet (with its position) or a truncated final group.
pub fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    // Any run of padding at the end is accepted, as written by any encoder.
    let text = text.trim_end_matches('=');
    TRACE_BASE64.decode(text).map_err(|e| match e {
        DecodeError::InvalidByte(i, c) => format!("invalid base64 character {:?} at position {i}", c as char),
        DecodeError::InvalidLength(_) => "truncated base64 (a final group of one character)".to_string(),
        // Neither can happen with trailing bits allowed and padding trimmed; named anyway.
        DecodeError::InvalidLastSymbol(i, c) => {
            format!("invalid final base64 character {:?} at position {i}", c as char)
        }
        DecodeError::InvalidPadding => "invalid base64 padding".to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_every_length() {
        let data: Vec<u8> = (0..=255u8).collect();
        for n in 0..40 {
            let encoded = encode_base64(&data[..n]);
            assert_eq!(decode_base64(&encoded).unwrap(), &data[..n], "length {n}");
        }
        assert_eq!(encode_base64(b"Man"), "TWFu");
        assert_eq!(encode_base64(b"Ma"), "TWE=");
        assert!(decode_base64("TW!u").is_err());
        assert!(decode_base64("T").is_err());
        // What the hand-written codec accepted: padding optional or repeated, stray low bits.
        assert_eq!(decode_base64("TWE").unwrap(), b"Ma");
        assert_eq!(decode_base64("TWE===").unwrap(), b"Ma");
        assert_eq!(decode_base64("TWF").unwrap(), b"Ma");
        assert_eq!(decode_base64("TW!u").unwrap_err(), "invalid base64 character '!' at position 2");
    }
}
