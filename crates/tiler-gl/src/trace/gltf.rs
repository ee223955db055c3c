//! Just enough glTF 2.0 to take mesh data from it: a primitive's attribute or index
//! accessor, as tightly packed elements. `.gltf` (JSON, buffers in files or `data:` URIs) and
//! `.glb` (binary container) are read; sparse accessors are refused.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::bytes::{Bytes, decode_base64};

/// Parsed glTF files, so several accessors of one file read it once.
#[derive(Default)]
pub(crate) struct Cache {
    documents: HashMap<PathBuf, Document>,
}

struct Document {
    json: Value,
    buffers: Vec<Bytes>,
}

const GLB_MAGIC: u32 = 0x4654_6c67; // "glTF"
const CHUNK_JSON: u32 = 0x4e4f_534a; // "JSON"
const CHUNK_BIN: u32 = 0x004e_4942; // "BIN\0"

impl Cache {
    /// The elements of the accessor a primitive uses for `attribute` (`"indices"` for its
    /// indices), and how many bytes of files were read to get them.
    ///
    /// # Errors
    /// Unreadable or malformed files, missing meshes, primitives, attributes or accessors,
    /// out-of-range views, sparse accessors, or files larger than `budget`.
    pub fn accessor(
        &mut self,
        path: &Path,
        mesh: u32,
        primitive: u32,
        attribute: &str,
        budget: u64,
    ) -> Result<(Bytes, u64), String> {
        let mut loaded = 0;
        if !self.documents.contains_key(path) {
            let (document, bytes) = load(path, budget)?;
            loaded = bytes;
            self.documents.insert(path.to_path_buf(), document);
        }
        let doc = &self.documents[path];
        let name = path.display();
        let fail = |what: String| format!("{name}: {what}");
        let prim = doc
            .json
            .pointer(&format!("/meshes/{mesh}/primitives/{primitive}"))
            .ok_or_else(|| fail(format!("no mesh {mesh} primitive {primitive}")))?;
        let accessor_index = if attribute == "indices" {
            prim.get("indices")
                .and_then(Value::as_u64)
                .ok_or_else(|| fail(format!("mesh {mesh} primitive {primitive} has no indices")))?
        } else {
            prim.pointer(&format!("/attributes/{attribute}"))
                .and_then(Value::as_u64)
                .ok_or_else(|| fail(format!("mesh {mesh} primitive {primitive} has no attribute {attribute}")))?
        };
        let acc = doc
            .json
            .pointer(&format!("/accessors/{accessor_index}"))
            .ok_or_else(|| fail(format!("no accessor {accessor_index}")))?;
        if acc.get("sparse").is_some() {
            return Err(fail(format!("accessor {accessor_index} is sparse, which is not supported")));
        }
        let count = acc
            .get("count")
            .and_then(Value::as_u64)
            .ok_or_else(|| fail(format!("accessor {accessor_index} has no count")))?;
        let component = match acc.get("componentType").and_then(Value::as_u64) {
            Some(5120 | 5121) => 1u64,
            Some(5122 | 5123) => 2,
            Some(5125 | 5126) => 4,
            other => return Err(fail(format!("accessor {accessor_index} has component type {other:?}"))),
        };
        let components = match acc.get("type").and_then(Value::as_str) {
            Some("SCALAR") => 1u64,
            Some("VEC2") => 2,
            Some("VEC3") => 3,
            Some("VEC4") => 4,
            Some("MAT2") => 4,
            Some("MAT3") => 9,
            Some("MAT4") => 16,
            other => return Err(fail(format!("accessor {accessor_index} has type {other:?}"))),
        };
        let element = component * components;
        let size = count.checked_mul(element).filter(|s| *s <= budget).ok_or_else(|| {
            fail(format!("accessor {accessor_index} ({count} elements of {element} bytes) is larger than allowed"))
        })?;
        let Some(view_index) = acc.get("bufferView").and_then(Value::as_u64) else {
            // No view: all zeros, as the specification says.
            return Ok((Bytes::from(vec![0u8; size as usize]), loaded));
        };
        let view = doc
            .json
            .pointer(&format!("/bufferViews/{view_index}"))
            .ok_or_else(|| fail(format!("no bufferView {view_index}")))?;
        let buffer = view
            .get("buffer")
            .and_then(Value::as_u64)
            .ok_or_else(|| fail(format!("bufferView {view_index} has no buffer")))?;
        let data = doc.buffers.get(buffer as usize).ok_or_else(|| fail(format!("no buffer {buffer}")))?;
        let view_offset = view.get("byteOffset").and_then(Value::as_u64).unwrap_or(0);
        let view_length = view.get("byteLength").and_then(Value::as_u64).unwrap_or(0);
        let stride = view.get("byteStride").and_then(Value::as_u64).unwrap_or(element).max(element);
        let offset = acc.get("byteOffset").and_then(Value::as_u64).unwrap_or(0);
        if view_offset.saturating_add(view_length) > data.len() as u64 {
            return Err(fail(format!("bufferView {view_index} runs past the end of buffer {buffer}")));
        }
        let needed = if count == 0 {
            0
        } else {
            offset.saturating_add((count - 1).saturating_mul(stride)).saturating_add(element)
        };
        if needed > view_length {
            return Err(fail(format!("accessor {accessor_index} runs past the end of bufferView {view_index}")));
        }
        let base = (view_offset + offset) as usize;
        let mut out = Vec::with_capacity(size as usize);
        for i in 0..count as usize {
            let start = base + i * stride as usize;
            out.extend_from_slice(&data[start..start + element as usize]);
        }
        if attribute == "indices" && component == 1 {
            out = out.iter().flat_map(|b| (*b as u16).to_le_bytes()).collect();
        }
        Ok((Bytes::from(out), loaded))
    }
}

/// Reads a `.gltf` or `.glb` file and its buffers.
fn load(path: &Path, budget: u64) -> Result<(Document, u64), String> {
    let name = path.display().to_string();
    let read = |p: &Path, loaded: &mut u64| -> Result<Vec<u8>, String> {
        let size = std::fs::metadata(p).map_err(|e| format!("{}: {e}", p.display()))?.len();
        *loaded += size;
        if *loaded > budget {
            return Err(format!("{}: the glTF data exceeds the trace's data limit", p.display()));
        }
        std::fs::read(p).map_err(|e| format!("{}: {e}", p.display()))
    };
    let mut loaded = 0;
    let bytes = read(path, &mut loaded)?;
    let word = |b: &[u8], at: usize| b.get(at..at + 4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]));
    let (json_bytes, bin) = if word(&bytes, 0) == Some(GLB_MAGIC) {
        let mut at = 12;
        let mut json = None;
        let mut bin = None;
        while let (Some(len), Some(kind)) = (word(&bytes, at), word(&bytes, at + 4)) {
            let start = at + 8;
            let end = start
                .checked_add(len as usize)
                .filter(|e| *e <= bytes.len())
                .ok_or_else(|| format!("{name}: a GLB chunk runs past the end"))?;
            match kind {
                CHUNK_JSON => json = Some(bytes[start..end].to_vec()),
                CHUNK_BIN => bin = Some(Bytes::from(&bytes[start..end])),
                _ => {}
            }
            at = end;
        }
        (json.ok_or_else(|| format!("{name}: a GLB without a JSON chunk"))?, bin)
    } else {
        (bytes, None)
    };
    let json: Value = serde_json::from_slice(&json_bytes).map_err(|e| format!("{name}: invalid glTF JSON: {e}"))?;
    let mut buffers = Vec::new();
    if let Some(list) = json.get("buffers").and_then(Value::as_array) {
        for (i, b) in list.iter().enumerate() {
            let data = match b.get("uri").and_then(Value::as_str) {
                None => bin
                    .clone()
                    .ok_or_else(|| format!("{name}: buffer {i} has no uri and there is no GLB binary chunk"))?,
                Some(uri) if uri.starts_with("data:") => {
                    let (_, payload) = uri
                        .split_once(";base64,")
                        .ok_or_else(|| format!("{name}: buffer {i}: only base64 data URIs are supported"))?;
                    loaded += payload.len() as u64;
                    if loaded > budget {
                        return Err(format!("{name}: the glTF data exceeds the trace's data limit"));
                    }
                    Bytes::from(decode_base64(payload).map_err(|e| format!("{name}: buffer {i}: {e}"))?)
                }
                Some(uri) => {
                    if uri.contains("..") || uri.starts_with('/') {
                        return Err(format!("{name}: buffer {i}: uri {uri:?} leaves the glTF's directory"));
                    }
                    let dir = path.parent().unwrap_or(Path::new(""));
                    Bytes::from(read(&dir.join(uri), &mut loaded)?)
                }
            };
            buffers.push(data);
        }
    }
    Ok((Document { json, buffers }, loaded))
}
