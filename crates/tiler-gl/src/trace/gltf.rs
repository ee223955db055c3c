//! Just enough glTF 2.0 to take mesh data from it: a primitive's attribute or index
//! accessor, as tightly packed elements. `.gltf` (JSON, buffers in files or `data:` URIs) and
//! `.glb` (binary container) are read; sparse accessors are refused.
//!
//! The `gltf` crate parses the file (the GLB container and the JSON, into its typed document);
//! this module only follows the indices a trace names — mesh, primitive, accessor, buffer
//! view, buffer — checking each where it is used, so a bad index is an error naming it rather
//! than a panic (the crate's validation would panic on some, and would refuse files the
//! trace reader has always taken, such as a `POSITION` accessor without `min` and `max`).
//! Buffers are read here too, within the trace's data limit and never outside the glTF's
//! folder.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use gltf::json::Root;
use gltf::json::validation::Checked;

use crate::bytes::{Bytes, decode_base64};

/// Parsed glTF files, so several accessors of one file read it once.
#[derive(Default)]
pub(crate) struct Cache {
    documents: HashMap<PathBuf, Document>,
}

struct Document {
    root: Root,
    buffers: Vec<Bytes>,
}

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
        let root = &doc.root;
        let name = path.display();
        let fail = |what: String| format!("{name}: {what}");
        let prim = root
            .meshes
            .get(mesh as usize)
            .and_then(|m| m.primitives.get(primitive as usize))
            .ok_or_else(|| fail(format!("no mesh {mesh} primitive {primitive}")))?;
        let accessor_index = if attribute == "indices" {
            prim.indices.ok_or_else(|| fail(format!("mesh {mesh} primitive {primitive} has no indices")))?
        } else {
            prim.attributes
                .iter()
                .find(|(semantic, _)| matches!(semantic, Checked::Valid(s) if s.to_string() == attribute))
                .map(|(_, accessor)| *accessor)
                .ok_or_else(|| fail(format!("mesh {mesh} primitive {primitive} has no attribute {attribute}")))?
        }
        .value();
        let acc = root.accessors.get(accessor_index).ok_or_else(|| fail(format!("no accessor {accessor_index}")))?;
        if acc.sparse.is_some() {
            return Err(fail(format!("accessor {accessor_index} is sparse, which is not supported")));
        }
        let count = acc.count.0;
        let component = match &acc.component_type {
            Checked::Valid(c) => c.0.size() as u64,
            Checked::Invalid => return Err(fail(format!("accessor {accessor_index} has an invalid component type"))),
        };
        let components = match &acc.type_ {
            Checked::Valid(t) => t.multiplicity() as u64,
            Checked::Invalid => return Err(fail(format!("accessor {accessor_index} has an invalid type"))),
        };
        let element = component * components;
        let size = count.checked_mul(element).filter(|s| *s <= budget).ok_or_else(|| {
            fail(format!("accessor {accessor_index} ({count} elements of {element} bytes) is larger than allowed"))
        })?;
        let Some(view_index) = acc.buffer_view.map(|v| v.value()) else {
            // No view: all zeros, as the specification says.
            return Ok((Bytes::from(vec![0u8; size as usize]), loaded));
        };
        let view = root.buffer_views.get(view_index).ok_or_else(|| fail(format!("no bufferView {view_index}")))?;
        let buffer = view.buffer.value();
        let data = doc.buffers.get(buffer).ok_or_else(|| fail(format!("no buffer {buffer}")))?;
        let view_offset = view.byte_offset.map_or(0, |o| o.0);
        let view_length = view.byte_length.0;
        let stride = view.byte_stride.map_or(element, |s| s.0 as u64).max(element);
        let offset = acc.byte_offset.map_or(0, |o| o.0);
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
    // Through tiler-io: regular files only (a FIFO or device is refused, not waited on or read
    // forever), read through what is left of the budget as bytes arrive.
    let read = |p: &Path, loaded: &mut u64| -> Result<Vec<u8>, String> {
        let bytes = tiler_io::read_file(p, budget.saturating_sub(*loaded))
            .map_err(|e| format!("{e} (the glTF data counts against the trace's data limit of {budget} bytes)"))?;
        *loaded += bytes.len() as u64;
        Ok(bytes)
    };
    let mut loaded = 0;
    let bytes = read(path, &mut loaded)?;
    let gltf = gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| match e {
        gltf::Error::Deserialize(e) => format!("{name}: invalid glTF JSON: {e}"),
        gltf::Error::Binary(e) => format!("{name}: invalid GLB container: {e}"),
        other => format!("{name}: invalid glTF: {other}"),
    })?;
    let bin = gltf.blob.map(Bytes::from);
    let root = gltf.document.into_json();
    let mut buffers = Vec::with_capacity(root.buffers.len());
    for (i, b) in root.buffers.iter().enumerate() {
        let data = match b.uri.as_deref() {
            None => {
                bin.clone().ok_or_else(|| format!("{name}: buffer {i} has no uri and there is no GLB binary chunk"))?
            }
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
                let dir = path.parent().unwrap_or(Path::new(""));
                let file = tiler_io::resolve_inside(dir, uri)
                    .map_err(|e| format!("{name}: buffer {i}: uri {uri:?} leaves the glTF's directory: {e}"))?;
                Bytes::from(read(&file, &mut loaded)?)
            }
        };
        buffers.push(data);
    }
    Ok((Document { root, buffers }, loaded))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A glTF of one triangle (positions, then u8 indices) in a folder of its own; the JSON is
    /// `edit`ed first.
    fn write(test: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
        let mut bin: Vec<u8> =
            [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0].iter().flat_map(|f| f.to_le_bytes()).collect();
        bin.extend([0u8, 1, 2]);
        let mut json = serde_json::json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": bin.len(), "uri": "t.bin"}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 3}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                          {"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}]
        });
        edit(&mut json);
        let dir = std::env::temp_dir().join(format!("tiler-gl-gltf-{}-{test}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("t.bin"), bin).unwrap();
        std::fs::write(dir.join("t.gltf"), json.to_string()).unwrap();
        dir.join("t.gltf")
    }

    fn read(path: &Path, attribute: &str) -> Result<Bytes, String> {
        Cache::default().accessor(path, 0, 0, attribute, 1 << 20).map(|(bytes, _)| bytes)
    }

    #[test]
    fn accessors_are_read_through_their_views() {
        let path = write("good", |_| {});
        assert_eq!(read(&path, "POSITION").unwrap().len(), 36);
        assert_eq!(read(&path, "indices").unwrap().as_slice(), &[0, 0, 1, 0, 2, 0], "u8 indices widened to u16");
    }

    #[test]
    fn bad_files_are_errors_that_name_what_and_where() {
        /// A name, an edit of the JSON, the attribute read, and what the error must say.
        type Case = (&'static str, fn(&mut serde_json::Value), &'static str, &'static str);
        let cases: [Case; 7] = [
            ("attribute", |_| {}, "NORMAL", "mesh 0 primitive 0 has no attribute NORMAL"),
            (
                "accessor",
                |j| j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9.into(),
                "POSITION",
                "no accessor 9",
            ),
            ("view", |j| j["accessors"][0]["bufferView"] = 5.into(), "POSITION", "no bufferView 5"),
            (
                "buffer",
                |j| j["bufferViews"][0]["byteLength"] = 400.into(),
                "POSITION",
                "bufferView 0 runs past the end of buffer 0",
            ),
            (
                "count",
                |j| j["accessors"][0]["count"] = 4.into(),
                "POSITION",
                "accessor 0 runs past the end of bufferView 0",
            ),
            (
                "uri",
                |j| j["buffers"][0]["uri"] = "../t.bin".into(),
                "POSITION",
                "buffer 0: uri \"../t.bin\" leaves the glTF's directory",
            ),
            ("json", |j| j["accessors"] = "none".into(), "POSITION", "invalid glTF JSON"),
        ];
        for (test, edit, attribute, expected) in cases {
            let path = write(test, edit);
            let error = read(&path, attribute).unwrap_err();
            assert!(error.starts_with(&path.display().to_string()), "{test}: {error}");
            assert!(error.contains(expected), "{test}: {error}");
        }
    }

    /// A buffer that is a FIFO, a device, or a link leading out of the folder is refused, not
    /// waited on, read forever or followed.
    #[cfg(unix)]
    #[test]
    fn buffers_must_be_regular_files_inside_the_folder() {
        /// A name, and how to make `t.bin` hostile.
        type Case = (&'static str, fn(&Path));
        let cases: [Case; 3] = [
            ("fifo", |bin| {
                let status = std::process::Command::new("mkfifo").arg(bin).status().unwrap();
                assert!(status.success());
            }),
            ("device", |bin| std::os::unix::fs::symlink("/dev/zero", bin).unwrap()),
            ("outside", |bin| {
                let outside = bin.parent().unwrap().with_extension("elsewhere");
                std::fs::write(&outside, b"hunter2-contents").unwrap();
                std::os::unix::fs::symlink(&outside, bin).unwrap();
            }),
        ];
        for (test, make) in cases {
            let path = write(test, |_| {});
            let bin = path.with_file_name("t.bin");
            std::fs::remove_file(&bin).unwrap();
            make(&bin);
            let error = read(&path, "POSITION").unwrap_err();
            assert!(error.contains("t.bin"), "{test}: {error}");
            assert!(!error.contains("hunter2"), "{test}: the error shows the file's bytes: {error}");
        }
    }

    #[test]
    fn a_truncated_glb_is_an_error() {
        let dir = std::env::temp_dir().join(format!("tiler-gl-gltf-{}-glb", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut glb = Vec::new();
        for word in [0x4654_6c67u32, 2, 100, 80, 0x4e4f_534a] {
            glb.extend(word.to_le_bytes());
        }
        glb.extend(b"{}");
        std::fs::write(dir.join("t.glb"), glb).unwrap();
        let error = read(&dir.join("t.glb"), "POSITION").unwrap_err();
        assert!(error.contains("invalid GLB container"), "{error}");
    }
}
