//! libFuzzer target: any bytes as a capture; reading and decoding must fail cleanly, never
//! panic, within the small limits. The input is taken both as a whole file and as an
//! uncompressed stream wrapped in one snappy chunk, so mutations reach the event parser and not
//! only the decompressor. Seed the corpus with small captures: `apitrace trim` one, or copy
//! `../shared/traces/glmark2/build.trace` into `corpus/capture/` (never into the repository).

#![no_main]

use libfuzzer_sys::fuzz_target;
use tiler_apitrace::{GlesReader, Limits};

fn read_all(bytes: &[u8]) {
    if let Ok(reader) = GlesReader::new(bytes, Limits::SMALL) {
        for call in reader {
            if call.is_err() {
                break;
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    read_all(data);
    if let Ok(compressed) = snap::raw::Encoder::new().compress_vec(data) {
        let mut file = b"at".to_vec();
        file.extend((compressed.len() as u32).to_le_bytes());
        file.extend(compressed);
        read_all(&file);
    }
});
