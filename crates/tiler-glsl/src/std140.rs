//! The `std140` layout of uniform blocks (GL ES 3.0 §2.12.6.4): where each member of a block
//! lies in its buffer, and how a block's bytes become the float components the program's
//! uniform storage holds (a struct's fields in order, arrays element by element, matrices
//! column by column, ints and bools as floats).
//!
//! The rules, with `N` = 4 bytes (a `float`, `int` or `bool`; a bool is true when non-zero):
//! - a scalar is aligned to `N`, a `vec2` to `2N`, a `vec3` or `vec4` to `4N` (rules 1–3);
//! - an array's elements are aligned and strided like a `vec4` at least (`4N`), and the
//!   array takes its stride × its length (rule 4);
//! - a `matC` is an array of `C` column vectors (rule 5);
//! - a struct is aligned like a `vec4` at least, its members laid out in order by these
//!   rules, and its size rounded up to its alignment (rule 9). A block is laid out as a
//!   struct.

use crate::types::{Scalar, Type};

/// `N`: the bytes of one component.
const N: usize = 4;

/// The base alignment of `ty` in bytes.
pub fn alignment(ty: &Type) -> usize {
    match ty {
        Type::Scalar(_) => N,
        Type::Vector(_, 2) => 2 * N,
        Type::Vector(..) => 4 * N,
        Type::Matrix(..) | Type::Array(..) => array_stride(ty).max(4 * N),
        Type::Struct(s) => s.fields.iter().map(|(_, t)| alignment(t)).max().unwrap_or(0).max(4 * N),
        Type::Void | Type::Sampler(_) => unreachable!("blocks hold no {ty} (checked at compile time)"),
    }
}

/// The stride between an array's elements, or a matrix's columns.
fn array_stride(ty: &Type) -> usize {
    match ty {
        Type::Matrix(..) => 4 * N,
        Type::Array(element, _) => round_up(size(element), alignment(element).max(4 * N)),
        _ => 0,
    }
}

/// The bytes `ty` takes in a block (a struct's size rounded up to its alignment).
pub fn size(ty: &Type) -> usize {
    match ty {
        Type::Scalar(_) => N,
        Type::Vector(_, n) => n * N,
        Type::Matrix(c, _) => c * array_stride(ty),
        Type::Array(_, n) => n * array_stride(ty),
        Type::Struct(s) => {
            let mut end = 0;
            for (_, t) in &s.fields {
                end = round_up(end, alignment(t)) + size(t);
            }
            round_up(end, alignment(ty))
        }
        Type::Void | Type::Sampler(_) => unreachable!("blocks hold no {ty} (checked at compile time)"),
    }
}

fn round_up(x: usize, to: usize) -> usize {
    x.div_ceil(to) * to
}

/// Appends the components of a `ty` at the start of `bytes` to `out`, in the order the
/// program's uniform storage holds them.
///
/// # Panics
/// If `bytes` is shorter than [`size`]`(ty)` (callers check).
pub fn read(ty: &Type, bytes: &[u8], out: &mut Vec<f32>) {
    let word = |at: usize| <[u8; 4]>::try_from(&bytes[at..at + 4]).expect("4 bytes");
    match ty {
        Type::Scalar(s) | Type::Vector(s, _) => {
            for k in 0..ty.size() {
                let w = word(k * N);
                out.push(match s {
                    Scalar::Float => f32::from_le_bytes(w),
                    // Integers are held as their bits (`ir`).
                    Scalar::Int | Scalar::UInt => f32::from_bits(u32::from_le_bytes(w)),
                    Scalar::Bool => f32::from(u8::from(u32::from_le_bytes(w) != 0)),
                });
            }
        }
        Type::Matrix(c, r) => {
            let stride = array_stride(ty);
            for column in 0..*c {
                read(&Type::vec(*r), &bytes[column * stride..], out);
            }
        }
        Type::Array(element, n) => {
            let stride = array_stride(ty);
            for k in 0..*n {
                read(element, &bytes[k * stride..], out);
            }
        }
        Type::Struct(s) => {
            let mut at = 0;
            for (_, t) in &s.fields {
                at = round_up(at, alignment(t));
                read(t, &bytes[at..], out);
                at += size(t);
            }
        }
        Type::Void | Type::Sampler(_) => unreachable!("blocks hold no {ty} (checked at compile time)"),
    }
}

#[cfg(test)]
mod tests {
    trait MapBits {
        fn map_bits(&self) -> Vec<u32>;
    }
    impl MapBits for Vec<f32> {
        fn map_bits(&self) -> Vec<u32> {
            self.iter().map(|x| x.to_bits()).collect()
        }
    }

    use std::sync::Arc;

    use super::*;
    use crate::types::StructType;

    fn block(fields: Vec<(&str, Type)>) -> Type {
        Type::Struct(Arc::new(StructType {
            name: "B".into(),
            fields: fields.into_iter().map(|(n, t)| (n.to_string(), t)).collect(),
        }))
    }

    /// A block exercising each rule, its offsets worked out by hand (in the comments); the
    /// padding word at 132 is not read.
    #[test]
    fn offsets_follow_the_std140_rules() {
        let inner = block(vec![("d", Type::Scalar(Scalar::Float)), ("e", Type::Vector(Scalar::Bool, 2))]);
        let b = block(vec![
            ("a", Type::Scalar(Scalar::Float)),                           // 0
            ("b", Type::vec(2)),                                          // 8
            ("c", Type::vec(3)),                                          // 16
            ("f", inner.clone()),                                         // 32 (d at 32, e at 40), size 16
            ("g", Type::Scalar(Scalar::Float)),                           // 48
            ("h", Type::Array(Box::new(Type::Scalar(Scalar::Float)), 2)), // 64, stride 16
            ("i", Type::Matrix(2, 2)),                                    // 96, columns at 96 and 112
            ("o", Type::Array(Box::new(inner), 2)),                       // 128 (d 128, e 136), 144 (d 144, e 152)
            ("p", Type::Vector(Scalar::Int, 3)),                          // 160
        ]);
        assert_eq!(size(&b), 176);
        let mut bytes = vec![0u8; 176];
        let mut put = |at: usize, v: [u8; 4]| bytes[at..at + 4].copy_from_slice(&v);
        let f = |x: f32| x.to_le_bytes();
        put(0, f(1.0));
        put(8, f(2.0));
        put(12, f(3.0));
        for (k, at) in [16, 20, 24].into_iter().enumerate() {
            put(at, f(4.0 + k as f32));
        }
        put(32, f(7.0));
        put(40, 0u32.to_le_bytes());
        put(44, 5u32.to_le_bytes());
        put(48, f(8.0));
        put(64, f(9.0));
        put(80, f(10.0));
        for (k, at) in [96, 100, 112, 116].into_iter().enumerate() {
            put(at, f(11.0 + k as f32));
        }
        put(128, f(15.0));
        put(132, 1u32.to_le_bytes());
        put(144, f(16.0));
        put(152, 1u32.to_le_bytes());
        for (k, at) in [160, 164, 168].into_iter().enumerate() {
            put(at, (-(k as i32) - 1).to_le_bytes());
        }
        let mut out = Vec::new();
        read(&b, &bytes, &mut out);
        assert_eq!(out.len(), b.size());
        let int = crate::exec::int;
        let want = [
            1.0,
            2.0,
            3.0,
            4.0,
            5.0,
            6.0,
            7.0,
            0.0,
            1.0,
            8.0,
            9.0,
            10.0,
            11.0,
            12.0,
            13.0,
            14.0,
            15.0,
            0.0,
            0.0,
            16.0,
            1.0,
            0.0,
            int(-1),
            int(-2),
            int(-3),
        ];
        // Integers are held as their bits (NaN patterns among them): compare bits.
        assert_eq!(out.map_bits(), want.map(f32::to_bits).to_vec());
    }
}
