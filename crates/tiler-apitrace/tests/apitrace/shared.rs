//! The shared glmark2 captures (skipped when ../shared is absent).

use std::collections::BTreeMap;

use tiler_apitrace::wire::{Compression, TraceReader};

use crate::common;

/// `SCENE-CALL.png` names of the llvmpipe reference frames: scene → sorted call numbers.
fn reference_swaps() -> Option<BTreeMap<String, Vec<u64>>> {
    let dir = common::reference_dir()?.join("glmark2");
    let mut swaps: BTreeMap<String, Vec<u64>> = BTreeMap::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        let Some(stem) = name.strip_suffix(".png") else { continue };
        let (scene, call) = stem.rsplit_once('-').unwrap();
        swaps.entry(scene.to_string()).or_default().push(call.parse().unwrap());
    }
    for calls in swaps.values_mut() {
        calls.sort();
    }
    Some(swaps)
}

#[test]
fn every_shared_capture_reads_whole_and_swaps_where_llvmpipe_did() {
    let Some(traces) = common::glmark2_traces() else { return };
    let Some(reference) = reference_swaps() else { return };
    assert_eq!(traces.len(), 10);
    for (scene, path) in &traces {
        let mut reader = TraceReader::open(path).unwrap();
        assert_eq!(reader.header().compression, Compression::Snappy);
        assert_eq!(reader.header().version, 6);
        let process = &reader.header().properties;
        assert!(
            process.iter().any(|(name, value)| name == "process.name" && value.contains("glmark2")),
            "{scene}: {process:?}"
        );
        let mut swaps = Vec::new();
        let mut last = None;
        for call in &mut reader {
            let call = call.unwrap_or_else(|e| panic!("{scene}: {e}"));
            assert!(!call.flags.incomplete, "{scene}: {call}");
            // glmark2 is single-threaded: calls leave in order.
            assert!(last.is_none_or(|last| call.number == last + 1), "{scene}: {call}");
            last = Some(call.number);
            if call.name() == "eglSwapBuffers" {
                swaps.push(call.number);
            }
        }
        assert_eq!(Some(&swaps), reference.get(scene), "{scene}");
    }
}

#[test]
fn every_call_of_the_shared_captures_decodes() {
    use tiler_apitrace::gles::{Command, GlesReader};
    let Some(traces) = common::glmark2_traces() else { return };
    let mut shaders = 0;
    for (scene, path) in &traces {
        // Buffer name → size, from glBufferData, to check where mapped writes land.
        let mut bound = 0;
        let mut sizes = std::collections::HashMap::new();
        let mut last_map = None;
        let mut writes = 0;
        for call in GlesReader::open(path).unwrap() {
            let call = call.unwrap_or_else(|e| panic!("{scene}: {e}"));
            match call.command {
                Command::ShaderSource { source, .. } => {
                    assert!(source.contains("main"), "{scene} call {}: {source}", call.number);
                    shaders += 1;
                }
                Command::BindBuffer { buffer, .. } => bound = buffer,
                Command::BufferData { size, .. } => {
                    sizes.insert(bound, size);
                }
                Command::MapBuffer { buffer, pointer, .. } => {
                    assert_ne!(pointer, 0, "{scene} call {}", call.number);
                    last_map = Some((call.number, buffer));
                }
                Command::BufferWrite { buffer, offset, data } => {
                    // The write follows the map of the same buffer, inside the buffer.
                    assert_eq!(last_map, Some((call.number - 1, buffer)), "{scene} call {}", call.number);
                    assert!(call.fake);
                    let size = sizes[&buffer];
                    assert!(
                        !data.is_empty() && offset + data.len() as u64 <= size,
                        "{scene} call {}: {offset} + {} > {size}",
                        call.number,
                        data.len()
                    );
                    writes += 1;
                }
                Command::UnmapBuffer { buffer, .. } => {
                    assert_eq!(last_map.map(|(_, b)| b), Some(buffer));
                }
                _ => {}
            }
        }
        // glmark2's buffer scene updates its four buffers through mappings every frame.
        assert_eq!(writes, if scene == "buffer" { 24 } else { 0 }, "{scene}");
    }
    assert_eq!(shaders, 40);
}

#[test]
fn uniforms_set_in_the_shared_captures_use_locations_the_captures_asked_for() {
    use std::collections::{HashMap, HashSet};
    use tiler_apitrace::gles::{Command, GlesReader};
    let Some(traces) = common::glmark2_traces() else { return };
    let mut checked = 0;
    for (scene, path) in &traces {
        let mut locations: HashMap<u32, HashSet<i32>> = HashMap::new();
        let mut program = 0;
        for call in GlesReader::open(path).unwrap() {
            let call = call.unwrap();
            match call.command {
                // Each capture recreates its context: names start over.
                Command::CreateContext { .. } => locations.clear(),
                Command::UniformLocation { program, location, .. } => {
                    locations.entry(program).or_default().insert(location);
                }
                Command::UseProgram { program: used } => program = used,
                Command::Uniform { location, .. } if location != -1 => {
                    let known = locations.get(&program).is_some_and(|l| l.contains(&location));
                    assert!(known, "{scene} call {}: location {location} of program {program}", call.number);
                    checked += 1;
                }
                _ => {}
            }
        }
    }
    assert!(checked > 100, "only {checked} uniform calls");
}
