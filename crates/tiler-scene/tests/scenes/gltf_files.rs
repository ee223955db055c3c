//! glTF files written by the tests themselves: every way of storing buffers and images, node
//! transforms, primitive modes, and one broken file for each error the loader reports.

use serde_json::{Value, json};
use tiler_scene::gltf::{AlphaMode, Model, load};
use tiler_scene::shading::Shading;

use crate::common::{base64, glb, png, quad, scratch_dir, write_gltf};

fn load_quad(name: &str, edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Result<Model, String> {
    let dir = scratch_dir(name);
    let (mut json, mut bin) = quad();
    edit(&mut json, &mut bin);
    let path = write_gltf(&dir, &format!("{name}.gltf"), &json, Some(&bin));
    load(&path, Shading::Scenes).map_err(|e| e.to_string())
}

/// Loading fails with a message naming the file and containing every `parts`.
fn assert_fails(name: &str, parts: &[&str], edit: impl FnOnce(&mut Value, &mut Vec<u8>)) {
    match load_quad(name, edit) {
        Ok(_) => panic!("{name}: loaded, but should fail"),
        Err(e) => {
            assert!(e.contains(&format!("{name}.gltf")), "{name}: the error does not name the file: {e}");
            for part in parts {
                assert!(e.contains(part), "{name}: expected '{part}' in: {e}");
            }
        }
    }
}

#[test]
fn external_buffer() {
    let model = load_quad("external", |_, _| {}).unwrap();
    assert_eq!(model.primitives.len(), 1);
    assert_eq!(model.triangles(), 2);
    let p = &model.primitives[0];
    assert_eq!(p.indices, [0, 1, 2, 0, 2, 3]);
    assert_eq!(p.vertices[2].position, [1.0, 1.0, 0.0]);
    assert_eq!(p.vertices[2].normal, [0.0, 0.0, 1.0]);
    assert_eq!(p.vertices[2].uv, [1.0, 0.0]);
    assert_eq!(model.materials[p.material].base_color_factor, [1.0, 0.5, 0.25, 1.0]);
    assert_eq!((model.min.to_array(), model.max.to_array()), ([-1.0, -1.0, 0.0], [1.0, 1.0, 0.0]));
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
}

#[test]
fn data_uri_buffer_and_image() {
    let texels = [255u8, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255];
    let model = load_quad("data_uri", |json, bin| {
        json["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{}", base64(bin)));
        json["images"] = json!([{"uri": format!("data:image/png;base64,{}", base64(&png(2, 2, &texels)))}]);
        json["textures"] = json!([{"source": 0}]);
        json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
        bin.clear(); // no quad.bin needed
    })
    .unwrap();
    assert_eq!(model.triangles(), 2);
    assert_eq!(model.textures_loaded, 1);
    let texture = &model.materials[0].base_color_texture.as_ref().unwrap().texture;
    assert_eq!((texture.width(), texture.height(), texture.levels().len()), (2, 2, 2));
    assert_eq!(texture.level_texels(0)[1], [0, 255, 0, 255]);
}

#[test]
fn glb_with_an_image_in_a_buffer_view() {
    let dir = scratch_dir("glb");
    let (mut json, mut bin) = quad();
    let image = png(1, 1, &[10, 20, 30, 255]);
    let image_offset = bin.len();
    bin.extend(&image);
    json["buffers"] = json!([{"byteLength": bin.len()}]);
    json["bufferViews"].as_array_mut().unwrap().push(json!({
        "buffer": 0, "byteOffset": image_offset, "byteLength": image.len()
    }));
    json["images"] = json!([{"bufferView": 2, "mimeType": "image/png"}]);
    json["textures"] = json!([{"source": 0, "sampler": 0}]);
    json["samplers"] = json!([{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33648}]);
    json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    let path = dir.join("model.glb");
    std::fs::write(&path, glb(&json, &bin)).unwrap();
    let model = load(&path, Shading::Scenes).unwrap();
    assert_eq!(model.triangles(), 2);
    let binding = model.materials[0].base_color_texture.as_ref().unwrap();
    assert_eq!(binding.texture.level_texels(0), &[[10, 20, 30, 255]]);
    // SCENES.md ignores the sampler; glTF shading honours it, and decodes sRGB.
    assert_eq!(binding.sampler, tiler::Sampler::TRILINEAR_REPEAT);
    let model = load(&path, Shading::Gltf).unwrap();
    let binding = model.materials[0].base_color_texture.as_ref().unwrap();
    let s = binding.sampler;
    assert_eq!(
        (s.mag_filter, s.min_filter, s.mipmap),
        (tiler::Filter::Nearest, tiler::Filter::Nearest, tiler::MipmapMode::None)
    );
    assert_eq!((s.wrap_u, s.wrap_v), (tiler::Wrap::ClampToEdge, tiler::Wrap::MirroredRepeat));
    assert_eq!(binding.texture.color_space(), tiler::ColorSpace::Srgb);
}

#[test]
fn percent_encoded_uri() {
    let dir = scratch_dir("percent");
    let (mut json, bin) = quad();
    std::fs::write(dir.join("my quad.bin"), &bin).unwrap();
    json["buffers"][0]["uri"] = json!("my%20quad.bin");
    let path = write_gltf(&dir, "percent.gltf", &json, None);
    assert_eq!(load(&path, Shading::Scenes).unwrap().triangles(), 2);
}

#[test]
fn node_hierarchy_and_instancing() {
    let model = load_quad("hierarchy", |json, _| {
        json["scenes"] = json!([{"nodes": [0, 2]}]);
        json["nodes"] = json!([
            {"translation": [10.0, 0.0, 0.0], "children": [1]},
            {"scale": [2.0, 2.0, 2.0], "mesh": 0},
            {"matrix": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 5.0, 0.0, 1.0], "mesh": 0}
        ]);
    })
    .unwrap();
    // The mesh is drawn once per node that uses it, in traversal order.
    assert_eq!(model.primitives.len(), 2);
    let (a, b) = (&model.primitives[0], &model.primitives[1]);
    assert_eq!((a.min, a.max), ([8.0, -2.0, 0.0], [12.0, 2.0, 0.0]));
    assert_eq!((b.min, b.max), ([-1.0, 4.0, 0.0], [1.0, 6.0, 0.0]));
    assert!(a.label.contains("node 1") && b.label.contains("node 2"), "{} / {}", a.label, b.label);
}

#[test]
fn mirroring_transform_keeps_front_faces() {
    let model = load_quad("mirror", |json, _| {
        json["nodes"][0]["scale"] = json!([-1.0, 1.0, 1.0]);
    })
    .unwrap();
    let p = &model.primitives[0];
    assert_eq!(p.indices, [0, 2, 1, 0, 3, 2]);
    assert_eq!(p.vertices[1].position, [-1.0, -1.0, 0.0]);
    assert_eq!(p.vertices[1].normal, [0.0, 0.0, 1.0]);
}

#[test]
fn strips_fans_and_skipped_modes() {
    let strip = load_quad("strip", |json, _| {
        let p = &mut json["meshes"][0]["primitives"][0];
        p["mode"] = json!(5);
        p.as_object_mut().unwrap().remove("indices");
    })
    .unwrap();
    assert_eq!(strip.primitives[0].indices, [0, 1, 2, 2, 1, 3]);
    let fan = load_quad("fan", |json, _| {
        json["meshes"][0]["primitives"][0]["mode"] = json!(6);
    })
    .unwrap();
    // Fan over indices [0, 1, 2, 0, 2, 3]: (1, 2, 0), (2, 0, 0), ... as glTF defines.
    assert_eq!(fan.primitives[0].triangles(), 4);
    assert_eq!(&fan.primitives[0].indices[..3], &[1, 2, 0]);
    let lines = load_quad("lines", |json, _| {
        let prims = json["meshes"][0]["primitives"].as_array_mut().unwrap();
        let mut line = prims[0].clone();
        line["mode"] = json!(1);
        prims.push(line);
    })
    .unwrap();
    assert_eq!(lines.primitives.len(), 1);
    assert!(lines.warnings.iter().any(|w| w.contains("mode Lines skipped")), "{:?}", lines.warnings);
}

#[test]
fn non_indexed_primitives_are_truncated_to_whole_triangles() {
    let model = load_quad("non_indexed", |json, _| {
        json["meshes"][0]["primitives"][0].as_object_mut().unwrap().remove("indices");
    })
    .unwrap();
    assert_eq!(model.primitives[0].indices, [0, 1, 2]);
}

#[test]
fn missing_normals_are_generated() {
    let remove_normals = |json: &mut Value, _: &mut Vec<u8>| {
        json["meshes"][0]["primitives"][0]["attributes"].as_object_mut().unwrap().remove("NORMAL");
    };
    // SCENES.md: per-vertex sums of face normals, on the shared vertices.
    let model = load_quad("no_normals", remove_normals).unwrap();
    let p = &model.primitives[0];
    assert_eq!(p.vertices.len(), 4);
    assert!(p.vertices.iter().all(|v| v.normal == [0.0, 0.0, 1.0]));
    // glTF: flat, every triangle with vertices of its own.
    let dir = scratch_dir("no_normals_gltf");
    let (mut json, mut bin) = quad();
    remove_normals(&mut json, &mut bin);
    let path = write_gltf(&dir, "flat.gltf", &json, Some(&bin));
    let model = load(&path, Shading::Gltf).unwrap();
    let p = &model.primitives[0];
    assert_eq!(p.vertices.len(), 6);
    assert_eq!(p.indices, [0, 1, 2, 3, 4, 5]);
    assert!(p.vertices.iter().all(|v| v.normal == [0.0, 0.0, 1.0]));
}

#[test]
fn normalized_integer_uvs() {
    let model = load_quad("u8_uvs", |json, bin| {
        // Replace the float uvs by normalised u8 pairs at the end of the buffer.
        let offset = bin.len();
        bin.extend([0u8, 255, 255, 255, 255, 0, 0, 0]);
        json["buffers"][0]["byteLength"] = json!(bin.len());
        json["bufferViews"].as_array_mut().unwrap().push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 8}));
        json["accessors"][2] =
            json!({"bufferView": 2, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"});
    })
    .unwrap();
    assert_eq!(model.primitives[0].vertices[1].uv, [1.0, 1.0]);
    assert_eq!(model.primitives[0].vertices[3].uv, [0.0, 0.0]);
}

#[test]
fn alpha_modes_and_double_sided() {
    let model = load_quad("alpha", |json, _| {
        json["materials"] = json!([{"alphaMode": "MASK", "alphaCutoff": 0.25, "doubleSided": true}]);
    })
    .unwrap();
    let m = &model.materials[0];
    assert_eq!(m.alpha_mode, AlphaMode::Mask { cutoff: 0.25 });
    assert!(m.double_sided);
    // A primitive without a material uses glTF's default material, listed last.
    let model = load_quad("no_material", |json, _| {
        json["meshes"][0]["primitives"][0].as_object_mut().unwrap().remove("material");
    })
    .unwrap();
    let m = &model.materials[model.primitives[0].material];
    assert_eq!((m.base_color_factor, m.alpha_mode), ([1.0; 4], AlphaMode::Opaque));
}

#[test]
fn cameras_of_the_scene_are_kept() {
    let model = load_quad("camera", |json, _| {
        json["scenes"] = json!([{"nodes": [0, 1]}]);
        json["nodes"] = json!([{"mesh": 0}, {"camera": 0, "translation": [0.0, 0.0, 5.0]}]);
        json["cameras"] = json!([{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]);
    })
    .unwrap();
    assert_eq!(model.cameras.len(), 1);
    let placement = tiler_scene::camera::place(&model, tiler_scene::camera::CameraChoice::Gltf(0), 2.0).unwrap();
    assert_eq!(placement.eye.to_array(), [0.0, 0.0, 5.0]);
    assert!(tiler_scene::camera::place(&model, tiler_scene::camera::CameraChoice::Gltf(1), 2.0).is_err());
}

#[test]
fn optional_extensions_warn() {
    let model = load_quad("optional_ext", |json, _| {
        json["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    })
    .unwrap();
    assert!(model.warnings.iter().any(|w| w.contains("KHR_materials_emissive_strength")), "{:?}", model.warnings);
}

#[test]
fn a_missing_image_is_a_warning_and_an_untextured_material() {
    let model = load_quad("missing_image", |json, _| {
        json["images"] = json!([{"uri": "nowhere.png"}]);
        json["textures"] = json!([{"source": 0}]);
        json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    })
    .unwrap();
    assert!(model.materials[0].base_color_texture.is_none());
    assert_eq!(model.textures_loaded, 0);
    assert!(model.warnings.iter().any(|w| w.contains("image 0") && w.contains("nowhere.png")), "{:?}", model.warnings);
}

#[test]
fn broken_json() {
    let dir = scratch_dir("bad_json");
    let path = dir.join("bad_json.gltf");
    std::fs::write(&path, b"{ \"asset\": { \"version\": \"2.0\" }, oops").unwrap();
    let e = load(&path, Shading::Scenes).unwrap_err().to_string();
    assert!(e.contains("bad_json.gltf") && e.contains("invalid glTF JSON"), "{e}");
    let e = load(&dir.join("absent.gltf"), Shading::Scenes).unwrap_err().to_string();
    assert!(e.contains("absent.gltf") && e.contains("cannot read"), "{e}");
}

#[test]
fn broken_glb() {
    let dir = scratch_dir("bad_glb");
    let (mut json, bin) = quad();
    json["buffers"] = json!([{"byteLength": bin.len()}]);
    let mut bytes = glb(&json, &bin);
    bytes.truncate(bytes.len() - 40);
    let path = dir.join("bad_glb.glb");
    std::fs::write(&path, bytes).unwrap();
    let e = load(&path, Shading::Scenes).unwrap_err().to_string();
    assert!(e.contains("bad_glb.glb") && e.contains("GLB"), "{e}");
}

#[test]
fn missing_buffer() {
    assert_fails("missing_buffer", &["buffer 0 (gone.bin)", "cannot read"], |json, _| {
        json["buffers"][0]["uri"] = json!("gone.bin");
    });
}

#[test]
fn short_buffer() {
    assert_fails("short_buffer", &["buffer 0 (quad.bin)", "100 bytes, but byteLength is 140"], |_, bin| {
        bin.truncate(100);
    });
}

#[test]
fn accessor_past_its_buffer_view() {
    assert_fails("accessor_range", &["mesh 0, primitive 0", "accessor 2", "buffer view 0 has 128"], |json, _| {
        json["accessors"][2]["count"] = json!(40);
    });
}

#[test]
fn buffer_view_past_its_buffer() {
    assert_fails("view_range", &["accessor 3", "buffer view 1", "past the end of buffer 0"], |json, _| {
        json["bufferViews"][1]["byteLength"] = json!(400);
    });
}

#[test]
fn index_out_of_range() {
    assert_fails("index_range", &["mesh 0, primitive 0", "index 9 at position 5", "4 vertices"], |_, bin| {
        let last = bin.len() - 2;
        bin[last..].copy_from_slice(&9u16.to_le_bytes());
    });
}

#[test]
fn accessor_index_out_of_range() {
    assert_fails("attribute_index", &["mesh 0, primitive 0", "POSITION", "accessor 17"], |json, _| {
        json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(17);
    });
    assert_fails("indices_index", &["meshes[0].primitives[0].indices"], |json, _| {
        json["meshes"][0]["primitives"][0]["indices"] = json!(9);
    });
}

#[test]
fn unsupported_component_types() {
    assert_fails("position_u16", &["POSITION (accessor 0)", "component type"], |json, _| {
        json["accessors"][0]["componentType"] = json!(5123);
    });
    assert_fails("float_indices", &["indices (accessor 3)", "component type"], |json, _| {
        json["accessors"][3]["componentType"] = json!(5126);
        json["accessors"][3]["count"] = json!(3);
    });
    assert_fails("unknown_type", &["accessors[0].componentType"], |json, _| {
        json["accessors"][0]["componentType"] = json!(5130);
    });
    assert_fails("wrong_shape", &["NORMAL (accessor 1)", "type Vec2, expected Vec3"], |json, _| {
        json["accessors"][1]["type"] = json!("VEC2");
    });
}

#[test]
fn required_extensions_are_refused() {
    assert_fails("draco", &["requires extension KHR_draco_mesh_compression"], |json, _| {
        json["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
        json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    });
    assert_fails("meshopt", &["requires extension EXT_meshopt_compression"], |json, _| {
        json["extensionsRequired"] = json!(["EXT_meshopt_compression"]);
    });
}

#[test]
fn sparse_accessors_are_refused() {
    assert_fails("sparse", &["accessor 0", "sparse accessors are not supported"], |json, _| {
        json["accessors"][0]["sparse"] = json!({
            "count": 1,
            "indices": {"bufferView": 1, "componentType": 5123},
            "values": {"bufferView": 0}
        });
    });
}

#[test]
fn node_cycles_are_refused() {
    assert_fails("cycle", &["node 0", "cycle"], |json, _| {
        json["nodes"] = json!([{"children": [1]}, {"children": [0], "mesh": 0}]);
    });
}

#[test]
fn non_finite_positions_are_refused() {
    assert_fails("nan", &["POSITION (accessor 0)", "vertex 1 is not finite"], |_, bin| {
        bin[12..16].copy_from_slice(&f32::NAN.to_le_bytes());
    });
}

#[test]
fn nothing_to_draw() {
    assert_fails("empty", &["no triangles"], |json, _| {
        json["meshes"][0]["primitives"][0]["mode"] = json!(0);
    });
}
