//! Data sources: how a trace gives bulk data — inline numbers, base64, a range of a binary
//! side file, or a glTF accessor — and reading them within a byte budget.

use std::collections::HashMap;
use std::path::PathBuf;

use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::bytes::{Bytes, ToLeBytes, decode_base64};

/// Where a call's bulk data comes from. In JSON, exactly one of:
///
/// - `{"f32": [..]}`, `{"u8": [..]}`, `{"u16": [..]}`, `{"u32": [..]}`, `{"i8": [..]}`,
///   `{"i16": [..]}`, `{"i32": [..]}`: numbers, written little-endian;
/// - `{"base64": "..."}`: bytes;
/// - `{"file": "frame.bin", "offset": 0, "length": 96}`: a range of a binary side file
///   (`offset` defaults to 0, `length` to the rest of the file);
/// - `{"gltf": "mesh.gltf", "mesh": 0, "primitive": 0, "attribute": "POSITION"}`: a glTF
///   accessor's elements, tightly packed (`"attribute": "indices"` gives the indices, u8
///   indices widened to u16).
#[derive(Clone, Debug, PartialEq)]
pub enum DataSource {
    F32(Vec<f32>),
    U8(Vec<u8>),
    U16(Vec<u16>),
    U32(Vec<u32>),
    I8(Vec<i8>),
    I16(Vec<i16>),
    I32(Vec<i32>),
    Base64(String),
    File { path: String, offset: u64, length: Option<u64> },
    Gltf { path: String, mesh: u32, primitive: u32, attribute: String },
}

#[derive(Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct Repr {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    f32: Option<Vec<f32>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    u8: Option<Vec<u8>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    u16: Option<Vec<u16>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    u32: Option<Vec<u32>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    i8: Option<Vec<i8>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    i16: Option<Vec<i16>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    i32: Option<Vec<i32>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    base64: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    file: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    offset: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    length: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    gltf: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mesh: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    primitive: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    attribute: Option<String>,
}

impl<'de> Deserialize<'de> for DataSource {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<DataSource, D::Error> {
        let r = Repr::deserialize(deserializer)?;
        let kinds = [
            r.f32.is_some(),
            r.u8.is_some(),
            r.u16.is_some(),
            r.u32.is_some(),
            r.i8.is_some(),
            r.i16.is_some(),
            r.i32.is_some(),
            r.base64.is_some(),
            r.file.is_some(),
            r.gltf.is_some(),
        ];
        let fail = |m: &str| Err(serde::de::Error::custom(m));
        if kinds.iter().filter(|k| **k).count() != 1 {
            return fail(
                "data must have exactly one of \"f32\", \"u8\", \"u16\", \"u32\", \"i8\", \"i16\", \"i32\", \
                 \"base64\", \"file\", \"gltf\"",
            );
        }
        let file_fields = r.offset.is_some() || r.length.is_some();
        let gltf_fields = r.mesh.is_some() || r.primitive.is_some() || r.attribute.is_some();
        if (file_fields && r.file.is_none()) || (gltf_fields && r.gltf.is_none()) {
            return fail("\"offset\"/\"length\" go with \"file\"; \"mesh\"/\"primitive\"/\"attribute\" with \"gltf\"");
        }
        Ok(if let Some(v) = r.f32 {
            DataSource::F32(v)
        } else if let Some(v) = r.u8 {
            DataSource::U8(v)
        } else if let Some(v) = r.u16 {
            DataSource::U16(v)
        } else if let Some(v) = r.u32 {
            DataSource::U32(v)
        } else if let Some(v) = r.i8 {
            DataSource::I8(v)
        } else if let Some(v) = r.i16 {
            DataSource::I16(v)
        } else if let Some(v) = r.i32 {
            DataSource::I32(v)
        } else if let Some(v) = r.base64 {
            DataSource::Base64(v)
        } else if let Some(path) = r.file {
            DataSource::File { path, offset: r.offset.unwrap_or(0), length: r.length }
        } else {
            let Some(attribute) = r.attribute else {
                return fail("a glTF source needs \"attribute\" (e.g. \"POSITION\", or \"indices\")");
            };
            DataSource::Gltf {
                path: r.gltf.expect("one kind"),
                mesh: r.mesh.unwrap_or(0),
                primitive: r.primitive.unwrap_or(0),
                attribute,
            }
        })
    }
}

impl Serialize for DataSource {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            DataSource::File { path, offset, length } => {
                let mut map = serializer.serialize_map(None)?;
                map.serialize_entry("file", path)?;
                map.serialize_entry("offset", offset)?;
                if let Some(length) = length {
                    map.serialize_entry("length", length)?;
                }
                map.end()
            }
            other => {
                let mut r = Repr::default();
                match other.clone() {
                    DataSource::F32(v) => r.f32 = Some(v),
                    DataSource::U8(v) => r.u8 = Some(v),
                    DataSource::U16(v) => r.u16 = Some(v),
                    DataSource::U32(v) => r.u32 = Some(v),
                    DataSource::I8(v) => r.i8 = Some(v),
                    DataSource::I16(v) => r.i16 = Some(v),
                    DataSource::I32(v) => r.i32 = Some(v),
                    DataSource::Base64(v) => r.base64 = Some(v),
                    DataSource::Gltf { path, mesh, primitive, attribute } => {
                        r.gltf = Some(path);
                        r.mesh = Some(mesh);
                        r.primitive = Some(primitive);
                        r.attribute = Some(attribute);
                    }
                    DataSource::File { .. } => unreachable!("handled above"),
                }
                r.serialize(serializer)
            }
        }
    }
}

/// Reads data sources into bytes, keeping count of what they pull in.
pub(crate) struct Resolver {
    base: Option<PathBuf>,
    budget: u64,
    used: u64,
    files: HashMap<PathBuf, Bytes>,
    gltf: super::gltf::Cache,
    /// Every file read, in the order first read.
    inputs: Vec<PathBuf>,
}

impl Resolver {
    pub fn new(base: Option<PathBuf>, budget: u64) -> Resolver {
        Resolver {
            base,
            budget,
            used: 0,
            files: HashMap::new(),
            gltf: super::gltf::Cache::default(),
            inputs: Vec::new(),
        }
    }

    /// The files the sources read (side files, glTF files), each once.
    pub fn into_inputs(self) -> Vec<PathBuf> {
        self.inputs
    }

    fn note_input(&mut self, path: &std::path::Path) {
        if !self.inputs.iter().any(|p| p == path) {
            self.inputs.push(path.to_path_buf());
        }
    }

    /// Counts `bytes` against the budget.
    ///
    /// # Errors
    /// The budget is exceeded.
    pub fn charge(&mut self, bytes: u64) -> Result<(), String> {
        self.used = self.used.saturating_add(bytes);
        if self.used > self.budget {
            return Err(format!("the trace's data exceeds its limit of {} bytes", self.budget));
        }
        Ok(())
    }

    /// The bytes of a source.
    ///
    /// # Errors
    /// Unreadable files, ranges past their end, malformed base64 or glTF, or too much data.
    pub fn resolve(&mut self, source: &DataSource) -> Result<Bytes, String> {
        fn numbers<T: ToLeBytes + Copy>(v: &[T]) -> Bytes {
            Bytes::from_slice(v)
        }
        let bytes = match source {
            DataSource::F32(v) => numbers(v),
            DataSource::U8(v) => Bytes::from(v.clone()),
            DataSource::U16(v) => numbers(v),
            DataSource::U32(v) => numbers(v),
            DataSource::I8(v) => numbers(v),
            DataSource::I16(v) => numbers(v),
            DataSource::I32(v) => numbers(v),
            DataSource::Base64(text) => Bytes::from(decode_base64(text)?),
            DataSource::File { path, offset, length } => {
                let full = super::resolve_path(&self.base, path)?;
                let file = match self.files.get(&full) {
                    Some(f) => f.clone(),
                    None => {
                        // Read through what is left of the budget, checked as bytes arrive.
                        let left = self.budget.saturating_sub(self.used);
                        let data = tiler_io::read_file(&full, left).map_err(|e| e.to_string())?;
                        self.charge(data.len() as u64)?;
                        self.note_input(&full);
                        let data = Bytes::from(data);
                        self.files.insert(full.clone(), data.clone());
                        data
                    }
                };
                let len = file.len() as u64;
                let length = length.unwrap_or(len.saturating_sub(*offset));
                let end = offset.checked_add(length).filter(|e| *e <= len).ok_or_else(|| {
                    format!(
                        "bytes {offset}..{} are past the end of {path} ({len} bytes)",
                        offset.saturating_add(length)
                    )
                })?;
                return Ok(Bytes::from(&file[*offset as usize..end as usize]));
            }
            DataSource::Gltf { path, mesh, primitive, attribute } => {
                let full = super::resolve_path(&self.base, path)?;
                // The glTF reader trusts the file's size: refuse devices and FIFOs here.
                tiler_io::check_regular_file(&full).map_err(|e| e.to_string())?;
                self.note_input(&full);
                let budget = self.budget.saturating_sub(self.used);
                let (bytes, loaded) = self.gltf.accessor(&full, *mesh, *primitive, attribute, budget)?;
                self.charge(loaded)?;
                bytes
            }
        };
        self.charge(bytes.len() as u64)?;
        Ok(bytes)
    }
}
