//! Frames: swaps, the frames in flight behind the CPU, and everything that waits on them —
//! read-backs, occlusion queries, `finish`, copy-on-write — plus the copies and blits that
//! read what earlier passes stored.
//!
//! # Frames in flight (seed 000 §23.6)
//!
//! A tiler processes a frame in three stages — the CPU builds it, the GPU's geometry phase
//! bins it, its fragment phase renders the tiles — and with balanced loads all three run at
//! once on consecutive frames. tiler-gl models this in whole frames: work submitted during
//! frame `N` completes while the CPU builds frame `N + L − 1` and its results are available
//! from frame `N + L`, where `L = frames_in_flight` (by default the backend's: 3 on a tiler,
//! one per stage, 2 in immediate mode — seed 000 §23.6). So:
//!
//! - an occlusion query ended in frame `N` reports available from frame `N + L`;
//! - asking for a result (`read_pixels`, `query_result`, `finish`) of work from frame `N`
//!   during frame `F < N + L` stalls the CPU until the pipeline has drained to it:
//!   `N + L − F` frames of lost pipelining (all `L` stages when it is this frame's work);
//! - a buffer or texture used by a draw of frame `N` is still in use by the GPU until frame
//!   `N + L`: changing it before then makes the driver copy it (copy-on-write).
//!
//! The passes themselves are rendered on the device as soon as they end (the model is only
//! about *when* results would be available on a real pipelined GPU), so images and counters do
//! not depend on `frames_in_flight`.

use tiler::{Category, ImageId};

use super::draw::{TexturedRect, gl_rect};
use super::pass::{OpenPass, defined_index, store_key};
use super::targets::{ColorTarget, Targets};
use super::{Context, Fallible, PendingStore};
use crate::call::{Filter, SwapBehavior};
use crate::report::{
    CopyOnWrite, DeadStore, DrawKind, EndCause, FlushCause, FrameRecord, LoadKind, Role, Slot, Stall, StallCause,
    StartCause, StoreKind,
};

/// The largest blit destination coordinate (`|x|`, `|y|`), keeping blits inside tiler's
/// viewport limits.
const MAX_BLIT_COORDINATE: i32 = 16384;

impl Context {
    /// Frames in flight: the configured figure, which [`Context::new`] fills in from the
    /// backend when the configuration leaves it out.
    pub(crate) fn frames_in_flight(&self) -> u32 {
        self.config.frames_in_flight.unwrap_or(self.config.backend.frames_in_flight())
    }

    /// Whether work of `frame` may still be running on the GPU.
    pub(crate) fn in_flight(&self, frame: u32) -> bool {
        self.here.frame < frame + self.frames_in_flight()
    }

    /// Records a stall waiting for the work of `frame`, if it is still in flight.
    fn stall_for(&mut self, frame: u32, cause: StallCause) {
        let frames = (frame + self.frames_in_flight()).saturating_sub(self.here.frame);
        if frames > 0 {
            self.frame.stalls.push(Stall { call: self.here, cause, waited_for_frame: frame, frames });
        }
    }

    /// Counts a copy-on-write of `bytes_copied` bytes of `object`. An update that replaces
    /// the whole object copies nothing (the driver gives it new storage: video players
    /// upload each frame's planes whole so), and is no copy-on-write.
    pub(crate) fn count_copy_on_write(&mut self, object: String, used_in_frame: u32, bytes_copied: u64) {
        if bytes_copied == 0 {
            return;
        }
        // Read the old contents and write the copy.
        let bytes = 2 * bytes_copied;
        self.frame.context_ledger.add(Category::CopyOnWrite, bytes);
        self.frame.copies.push(CopyOnWrite { call: self.here, object, used_in_frame, bytes_copied, bytes });
    }

    // --- the store tracker: which stored contents were never read --------------------------

    /// A pass stored an aspect of an image; an earlier store nobody read was wasted if this
    /// one covers the whole image (a store of part of it, in a tiled-rendering region, keeps
    /// the rest).
    pub(crate) fn register_store(&mut self, image: ImageId, slot: Slot, pass: u32, bytes: u64, whole: bool) {
        let key = store_key(image, slot);
        let store = PendingStore { pass, frame: self.here.frame, bytes, consumed: false };
        if let Some(old) = self.stores.insert(key, store)
            && whole
        {
            self.dead_if_unread(key, old, format!("overwritten by pass {pass}"));
        }
    }

    /// The stored contents of an aspect were read.
    pub(crate) fn consume(&mut self, image: ImageId, slot: Slot) {
        if let Some(s) = self.stores.get_mut(&store_key(image, slot)) {
            s.consumed = true;
        }
    }

    /// The stored contents of an aspect stop mattering.
    fn kill_store(&mut self, image: ImageId, slot: Slot, fate: &str) {
        let key = store_key(image, slot);
        if let Some(old) = self.stores.remove(&key) {
            self.dead_if_unread(key, old, fate.to_string());
        }
    }

    /// Every aspect of an image stops mattering.
    pub(crate) fn forget_stores(&mut self, image: ImageId, fate: &str) {
        for slot in [Slot::Color(0), Slot::Depth, Slot::Stencil] {
            self.kill_store(image, slot, fate);
        }
    }

    fn dead_if_unread(&mut self, (image, slot): (ImageId, Slot), store: PendingStore, fate: String) {
        if !store.consumed {
            self.frame.dead_stores.push(DeadStore {
                pass: store.pass,
                frame: store.frame,
                slot,
                image,
                bytes: store.bytes,
                fate,
            });
        }
    }

    /// An aspect's contents are undefined from now on.
    pub(crate) fn undefine(&mut self, image: ImageId, slot: Slot, why: &str) {
        if let Some(info) = self.images.get_mut(&image) {
            info.defined[defined_index(slot)] = false;
        }
        self.kill_store(image, slot, why);
    }

    // --- swaps ------------------------------------------------------------------------------

    /// `eglSwapBuffers`: renders what is pending, shows the window, and starts a new frame.
    pub(crate) fn swap_buffers(&mut self) -> Fallible {
        if self.tiling.is_some() {
            return Err("swap_buffers inside a tiled-rendering region: call end_tiling first".to_string());
        }
        self.end_open_pass(EndCause::Swap)?;
        let color = self.surface_color;
        // The display model of the device: scan-out and, if configured, composition.
        let present = self.device.present(color).map_err(|e| e.to_string())?;
        self.frame.context_ledger.merge(&present);
        if self.config.digest_presented {
            let rgba = self.surface_rgba8();
            self.frame.presented_digest =
                Some(crate::report::picture_digest(self.config.width, self.config.height, &rgba));
        }
        // The display reads the colour buffer.
        self.consume(color, Slot::Color(0));
        if self.swap_behavior == SwapBehavior::Destroyed {
            self.undefine(color, Slot::Color(0), "destroyed by the swap");
        }
        if let Some(ds) = self.surface_depth_stencil {
            self.undefine(ds, Slot::Depth, "undefined after the swap");
            self.undefine(ds, Slot::Stencil, "undefined after the swap");
        }
        self.frame.swapped = true;
        self.close_frame();
        self.next_start = (StartCause::NewFrame, self.here);
        Ok(())
    }

    /// Ends the frame being built and starts the next.
    fn close_frame(&mut self) {
        let next = FrameRecord {
            index: self.here.frame + 1,
            latency_frames: self.frames_in_flight(),
            ..FrameRecord::default()
        };
        let mut done = std::mem::replace(&mut self.frame, next);
        done.calls = self.here.call + u32::from(done.swapped);
        done.total();
        self.frames.push(done);
        self.here = crate::report::CallRef::new(self.here.frame + 1, 0);
    }

    /// Renders whatever is pending and closes the current frame (when it did anything): the
    /// end of a trace or a program. Stored depth and stencil nobody read are reported then.
    pub(crate) fn end_run(&mut self) -> Fallible {
        self.end_open_pass(EndCause::End)?;
        // In image and aspect order: the map's own order would differ from run to run.
        let mut keys: Vec<_> = self.stores.keys().copied().filter(|(_, slot)| *slot != Slot::Color(0)).collect();
        keys.sort();
        for (image, slot) in keys {
            self.kill_store(image, slot, "never read before the end");
        }
        if self.here.call > 0 || !self.frame.passes.is_empty() || !self.frame.dead_stores.is_empty() {
            self.close_frame();
        }
        Ok(())
    }

    // --- results the CPU waits for ---------------------------------------------------------

    /// `glFinish`: flushes, and waits for everything submitted.
    pub(crate) fn finish(&mut self) -> Fallible {
        self.flush_open_pass(FlushCause::Finish)?;
        if let Some(frame) = self.last_submit_frame {
            self.stall_for(frame, StallCause::Finish);
        }
        Ok(())
    }

    /// `fence_sync`: a fence after the commands so far.
    pub(crate) fn fence_sync(&mut self, id: u32) -> Fallible {
        if self.fences.contains_key(&id) {
            return Err(format!("fence {id} already exists"));
        }
        let open = self.pass.as_ref().is_some_and(|p| p.has_work()).then_some(self.passes_rendered);
        self.fences.insert(id, (self.here.frame, open));
        Ok(())
    }

    /// `client_wait_sync`: the CPU waits for the commands before fence `id`. The pass holding
    /// some of them, if still open, is flushed; the wait stalls as a query's result does when
    /// the fence's frame is still in flight (seed 000 §23.6), and not when it is frames in
    /// flight old — how applications pace their frames (mpv waits on the fence of two frames
    /// before).
    pub(crate) fn client_wait_sync(&mut self, id: u32) -> Fallible {
        let &(frame, open) = self.fences.get(&id).ok_or_else(|| format!("fence {id} does not exist"))?;
        if open.is_some_and(|rendered| rendered == self.passes_rendered)
            && self.pass.as_ref().is_some_and(|p| p.has_work())
        {
            self.flush_open_pass(FlushCause::Finish)?;
        }
        if self.here.frame < frame + self.frames_in_flight() {
            self.stall_for(frame, StallCause::FenceWait);
        }
        Ok(())
    }

    /// The window's colour now, RGBA8 rows top first: an open pass drawing into the window
    /// renders first, as for a `glReadPixels` of it (counted as one: the pass stores, and
    /// drawing continues in a new pass that loads). For looking at a capture that never
    /// swaps (`tiler analyze --snapshot`).
    ///
    /// # Errors
    /// Inside an explicit render pass (`begin_pass`), which cannot be split.
    pub fn window_snapshot(&mut self) -> Result<Vec<u8>, String> {
        if self.pass.as_ref().is_some_and(|p| p.framebuffer == 0 && p.copy_texture.is_none()) {
            self.flush_open_pass(FlushCause::ReadPixels)?;
        }
        Ok(self.surface_rgba8())
    }

    /// The picture of the framebuffer bound for drawing now, RGBA8 rows top first, with its
    /// width and height: the window (as [`Context::window_snapshot`]) or a framebuffer
    /// object's first colour attachment (its resolved image when it is multisampled). An open
    /// pass drawing into it renders first, as for a `glReadPixels`. For `tiler analyze
    /// --snapshot`: what a render-to-texture pass has drawn so far.
    ///
    /// # Errors
    /// Inside an explicit render pass; a framebuffer object without a colour attachment.
    pub fn draw_snapshot(&mut self) -> Result<(u32, u32, Vec<u8>), String> {
        let fb = self.draw_framebuffer;
        if fb == 0 {
            let (width, height) = (self.config.width, self.config.height);
            return Ok((width, height, self.window_snapshot()?));
        }
        let source = self.targets(fb)?;
        let image = source
            .color
            .first()
            .ok_or_else(|| format!("framebuffer {fb} has no colour attachment to show"))?
            .readable();
        self.check_has_memory(image, &format!("snapshot of framebuffer {fb}'s color0"))?;
        if self.pass.as_ref().is_some_and(|p| p.framebuffer == fb && p.copy_texture.is_none()) {
            self.flush_open_pass(FlushCause::ReadPixels)?;
        }
        let rgba = self.device.read_rgba8(image).map_err(|e| e.to_string())?;
        Ok((source.width, source.height, rgba))
    }

    /// `glReadPixels` of the read framebuffer's first colour attachment: RGBA8, or with
    /// `integer` (`Some(signed)`, `GL_RGBA_INTEGER` of `GL_INT` or `GL_UNSIGNED_INT`) an integer
    /// attachment's four channels as 32-bit little-endian integers (missing ones 0, alpha 1).
    pub(crate) fn read_pixels(
        &mut self,
        x: i32,
        y: i32,
        width: u32,
        height: u32,
        integer: Option<bool>,
    ) -> Fallible<Vec<u8>> {
        let read = self.read_framebuffer;
        let source = self.targets(read)?;
        let image = source
            .color
            .first()
            .ok_or_else(|| format!("framebuffer {read} has no colour attachment to read"))?
            .readable();
        self.check_has_memory(image, &format!("read_pixels of framebuffer {read}'s color0"))?;
        let format = self.images[&image].desc.format;
        match (format, integer) {
            (tiler::Format::Int(f), Some(signed)) if f.signed == signed => {}
            (f, None) if !f.is_integer() => {}
            (f, integer) => {
                return Err(format!(
                    "read_pixels of framebuffer {read}'s color0 ({f}) as {}: GL ES 3.0 reads an integer buffer as \
                     RGBA_INTEGER of its signedness's INT type, and others as RGBA bytes (GL_INVALID_OPERATION)",
                    match integer {
                        Some(true) => "RGBA_INTEGER / INT",
                        Some(false) => "RGBA_INTEGER / UNSIGNED_INT",
                        None => "RGBA / UNSIGNED_BYTE",
                    }
                ));
            }
        }
        if self.images[&image].desc.samples > 1 {
            return Err(format!(
                "framebuffer {read} is multisampled (GL_INVALID_OPERATION): blit it to a single-sampled framebuffer first"
            ));
        }
        if x < 0
            || y < 0
            || x as u64 + width as u64 > source.width as u64
            || y as u64 + height as u64 > source.height as u64
        {
            return Err(format!(
                "rectangle {width}×{height} at ({x}, {y}) is not inside framebuffer {read} ({}×{})",
                source.width, source.height
            ));
        }
        if self.pass.as_ref().is_some_and(|p| p.framebuffer == read && p.copy_texture.is_none()) {
            self.flush_open_pass(FlushCause::ReadPixels)?;
        }
        if let Some(frame) = self.images[&image].last_write {
            self.stall_for(frame, StallCause::ReadPixels);
        }
        self.consume(image, Slot::Color(0));
        let frame = self.here.frame;
        self.images.get_mut(&image).expect("attached").last_use = Some(frame);
        let w = source.width as usize;
        if let tiler::Format::Int(f) = format {
            let data = self.device.image_data(image).map_err(|e| e.to_string())?;
            let mut out = Vec::with_capacity(width as usize * height as usize * 16);
            for r in 0..height as usize {
                let row = source.height as usize - 1 - (y as usize + r);
                for px in row * w + x as usize..row * w + x as usize + width as usize {
                    let texel = f.unpack(&data[px * f.bytes()..(px + 1) * f.bytes()]);
                    out.extend(texel.iter().flat_map(|c| c.to_le_bytes()));
                }
            }
            return Ok(out);
        }
        let rgba = self.device.read_rgba8(image).map_err(|e| e.to_string())?;
        let mut out = Vec::with_capacity(width as usize * height as usize * 4);
        for r in 0..height as usize {
            let row = source.height as usize - 1 - (y as usize + r);
            out.extend_from_slice(&rgba[(row * w + x as usize) * 4..(row * w + x as usize + width as usize) * 4]);
        }
        Ok(out)
    }

    /// `GL_QUERY_RESULT_AVAILABLE`: never waits.
    pub(crate) fn query_available(&mut self, id: u32) -> Fallible<bool> {
        let q = self.queries.get(&id).ok_or_else(|| format!("query {id} does not exist"))?;
        if self.active_query == Some(id) {
            return Err(format!("query {id} is active: end it first"));
        }
        if !q.ended {
            return Err(format!("query {id} has never been ended"));
        }
        Ok(q.pending_draws == 0 && self.here.frame >= q.last_frame + self.frames_in_flight())
    }

    /// `GL_QUERY_RESULT`: flushes the pass holding the query's draws, waits if the result
    /// is not available yet, and returns the samples that passed.
    pub(crate) fn query_result(&mut self, id: u32) -> Fallible<u64> {
        let available = self.query_available(id)?;
        if !available {
            if self.queries[&id].pending_draws > 0 {
                self.flush_open_pass(FlushCause::QueryResult)?;
            }
            let frame = self.queries[&id].last_frame;
            self.stall_for(frame, StallCause::QueryResult);
        }
        Ok(self.queries[&id].samples)
    }

    // --- copies and blits ------------------------------------------------------------------

    /// `glBlitFramebuffer` of colour: a textured rectangle drawn into the draw framebuffer's
    /// pass, reading the read framebuffer's first colour attachment (`texture_fetch`:
    /// `source pixels × samples × bytes per sample`; a multisampled source is averaged, a
    /// resolve).
    pub(crate) fn blit(&mut self, src: [i32; 4], dst: [i32; 4], filter: Filter) -> Fallible {
        self.outside_explicit_pass("blit_framebuffer")?;
        let (read, draw) = (self.read_framebuffer, self.draw_framebuffer);
        if read == draw {
            return Err(format!(
                "blit_framebuffer from framebuffer {read} to itself: bind different read and draw framebuffers"
            ));
        }
        let source = self.targets(read)?;
        let image =
            source.color.first().ok_or_else(|| format!("framebuffer {read} has no colour attachment"))?.readable();
        self.check_has_memory(image, &format!("blit_framebuffer from framebuffer {read}'s color0"))?;
        let (sw, sh) = (source.width as i32, source.height as i32);
        if src.iter().enumerate().any(|(i, v)| *v < 0 || *v > if i % 2 == 0 { sw } else { sh }) {
            return Err(format!("source rectangle {src:?} is not inside framebuffer {read} ({sw}×{sh})"));
        }
        if dst.iter().any(|v| v.abs() > MAX_BLIT_COORDINATE) {
            return Err(format!("destination rectangle {dst:?} has a coordinate beyond ±{MAX_BLIT_COORDINATE}"));
        }
        let source_pixels = (src[2] - src[0]).unsigned_abs() as u64 * (src[3] - src[1]).unsigned_abs() as u64;
        if source_pixels == 0 || dst[0] == dst[2] || dst[1] == dst[3] {
            return Ok(());
        }
        let desc = self.images[&image].desc;
        let to_integer = self.ensure_pass()?.targets.color.first().is_some_and(|c| c.format.format().is_integer());
        if desc.format.is_integer() || to_integer {
            return Err(format!(
                "blit_framebuffer from framebuffer {read} ({}): blits of integer colour buffers are not supported",
                desc.format
            ));
        }
        let read_bytes = source_pixels * desc.samples as u64 * desc.format.bytes_per_sample() as u64;
        let targets = self.ensure_pass()?.targets.clone();
        let (dw, dh) = (targets.width as f32, targets.height as f32);
        let xn = |x: i32| 2.0 * x as f32 / dw - 1.0;
        let yn = |y: i32| 2.0 * (dh - y as f32) / dh - 1.0;
        let ndc = [xn(dst[0]), yn(dst[3]), xn(dst[2]), yn(dst[1])];
        let tex = [
            src[0] as f32 / sw as f32,
            src[3] as f32 / sh as f32,
            src[2] as f32 / sw as f32,
            src[1] as f32 / sh as f32,
        ];
        let (x0, x1) = (dst[0].min(dst[2]) as i64, dst[0].max(dst[2]) as i64);
        let (y0, y1) = (dst[1].min(dst[3]) as i64, dst[1].max(dst[3]) as i64);
        let rect = gl_rect(x0, y0, x1 - x0, y1 - y0, targets.width, targets.height);
        let s = &self.state;
        let scissor = s
            .scissor_test
            .then(|| gl_rect(s.scissor[0], s.scissor[1], s.scissor[2], s.scissor[3], targets.width, targets.height));
        self.push_rectangle(TexturedRect {
            kind: DrawKind::Blit,
            image,
            dst: rect,
            ndc,
            tex,
            filter,
            read_bytes,
            scissor,
            alpha_one: false,
        })?;
        self.sampled(image, self.here.frame);
        Ok(())
    }

    /// `glCopyTexSubImage2D`: renders a pass into the texture, drawing the read framebuffer's
    /// rectangle into it. The pass loads the texture only when the copy covers part of it.
    /// `alpha_one`: the texels copied get alpha 1 (a texture without alpha).
    pub(crate) fn copy_tex_sub_image(
        &mut self,
        texture: u32,
        [x_offset, y_offset]: [u32; 2],
        [x, y]: [i32; 2],
        [width, height]: [u32; 2],
        alpha_one: bool,
    ) -> Fallible {
        self.outside_explicit_pass("copy_tex_sub_image")?;
        let read = self.read_framebuffer;
        let source = self.targets(read)?;
        let src_image =
            source.color.first().ok_or_else(|| format!("framebuffer {read} has no colour attachment"))?.readable();
        self.check_has_memory(src_image, &format!("copy_tex_sub_image from framebuffer {read}'s color0"))?;
        let t = self.texture(texture)?;
        let (dst_image, dst_format) = (t.image, t.format);
        self.check_has_memory(dst_image, &format!("copy_tex_sub_image into texture {texture}"))?;
        if !dst_format.is_color() {
            return Err(format!("texture {texture} has format {}, not a colour format", dst_format.name()));
        }
        let dd = self.images[&dst_image].desc;
        if x_offset as u64 + width as u64 > dd.width as u64 || y_offset as u64 + height as u64 > dd.height as u64 {
            return Err(format!(
                "a {width}×{height} copy at ({x_offset}, {y_offset}) does not fit texture {texture} ({}×{})",
                dd.width, dd.height
            ));
        }
        if x < 0
            || y < 0
            || x as u64 + width as u64 > source.width as u64
            || y as u64 + height as u64 > source.height as u64
        {
            return Err(format!(
                "source rectangle {width}×{height} at ({x}, {y}) is not inside framebuffer {read} ({}×{})",
                source.width, source.height
            ));
        }
        if width == 0 || height == 0 {
            return Ok(());
        }
        // Copies flush: the read framebuffer's pending work, and a pass that uses the texture.
        if self.pass.as_ref().is_some_and(|p| {
            p.has_work()
                && (p.framebuffer == read
                    || p.images_sampled.contains(&dst_image)
                    || p.targets.images().any(|i| i == dst_image))
        }) {
            self.flush_open_pass(FlushCause::CopyTexImage)?;
        }
        let here = self.here;
        let region = gl_rect(x_offset as i64, y_offset as i64, width as i64, height as i64, dd.width, dd.height);
        let full = region.area() == dd.width as u64 * dd.height as u64;
        let defined = self.images[&dst_image].defined[0];
        let (load, load_reason) = if full {
            (LoadKind::DontCare, "the copy overwrites the whole texture".to_string())
        } else if defined {
            (LoadKind::Load, "the copy covers part of the texture; the rest is kept".to_string())
        } else {
            (LoadKind::DontCare, "its contents are undefined".to_string())
        };
        let aspect = super::pass::PassAspect {
            slot: Slot::Color(0),
            image: dst_image,
            role: Role::Attached,
            load,
            clear: [0.0; 4],
            load_reason,
            store: StoreKind::Store,
            store_reason: "the copied texels".to_string(),
            invalidated: false,
            resolve: None,
            transient: false,
        };
        let copy = OpenPass {
            framebuffer: read,
            copy_texture: Some(texture),
            window_preserved: false,
            targets: Targets {
                color: vec![ColorTarget { image: dst_image, format: dst_format, resolve: None }],
                depth_stencil: None,
                width: dd.width,
                height: dd.height,
                samples: dd.samples,
            },
            aspects: vec![aspect],
            draws: Vec::new(),
            start: StartCause::Copy,
            started_at: here,
            region: (!full).then_some(region),
            dropped: Vec::new(),
            buffers_used: Default::default(),
            images_sampled: Default::default(),
            retired_buffers: Vec::new(),
            retired_images: Vec::new(),
            explicit: None,
        };
        let src_desc = self.images[&src_image].desc;
        let read_bytes =
            width as u64 * height as u64 * src_desc.samples as u64 * src_desc.format.bytes_per_sample() as u64;
        let (sw, sh) = (source.width as f32, source.height as f32);
        let tex = [
            x as f32 / sw,
            (y as u64 + height as u64) as f32 / sh,
            (x as u64 + width as u64) as f32 / sw,
            y as f32 / sh,
        ];
        let (tw, th) = (dd.width as f32, dd.height as f32);
        let ndc = [
            2.0 * region.x as f32 / tw - 1.0,
            2.0 * region.y as f32 / th - 1.0,
            2.0 * region.right() as f32 / tw - 1.0,
            2.0 * region.bottom() as f32 / th - 1.0,
        ];
        let saved = self.pass.replace(copy);
        let result = self
            .push_rectangle(TexturedRect {
                kind: DrawKind::Copy,
                image: src_image,
                dst: region,
                ndc,
                tex,
                filter: Filter::Nearest,
                read_bytes,
                scissor: None,
                alpha_one,
            })
            .and_then(|()| {
                self.sampled(src_image, here.frame);
                self.end_open_pass(EndCause::Copy)
            });
        self.pass = saved;
        result
    }
}
