//! Every model of `../shared/assets` loads, in both shading modes, with the triangle counts its
//! README gives (as drawn: instanced meshes count once per node).

use tiler_scene::gltf::load;
use tiler_scene::shading::Shading;

use crate::common::assets_dir;

const MODELS: [(&str, u64); 15] = [
    ("AlphaBlendModeTest", 61),
    ("Avocado", 682),
    ("Box", 12),
    ("BoxInterleaved", 12),
    ("BoxTextured", 12),
    ("BoxVertexColors", 12),
    ("DamagedHelmet", 15_452),
    ("Duck", 4_212),
    ("FlightHelmet", 94_722),
    ("ReciprocatingSaw", 198_470),
    ("TextureCoordinateTest", 10),
    ("TextureSettingsTest", 72),
    ("TriangleWithoutIndices", 1),
    ("TwoSidedPlane", 2),
    ("VC", 8_383),
];

#[test]
fn every_model_loads() {
    let Some(assets) = assets_dir() else { return };
    for (name, triangles) in MODELS {
        let path = assets.join(name).join(format!("{name}.gltf"));
        for shading in [Shading::Scenes, Shading::Gltf] {
            let model = load(&path, shading).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(model.triangles(), triangles, "{name} ({shading:?})");
            let missing: Vec<&String> = model.warnings.iter().filter(|w| w.contains("cannot read")).collect();
            // FlightHelmet lacks its leather base colour (MISSING.md): a warning, not an error.
            assert_eq!(missing.len(), usize::from(name == "FlightHelmet"), "{name}: {missing:?}");
        }
    }
}
