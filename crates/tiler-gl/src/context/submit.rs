//! Submission: an ended pass becomes a `tiler::RenderPass` — attachments with the load and
//! store ops `pass.rs` inferred, the gathered draws with their programs, uniforms and
//! textures — rendered on the device at once; its report becomes the pass's record
//! (attachments, draws, cost) and the store tracker learns what it stored. Also what a
//! submission reads: textures through the core's sampler or a decoded snapshot, once per
//! submission.

use std::collections::HashMap;
use std::sync::Arc;

use tiler::{ColorAttachment, DepthStencilAttachment, Draw, ImageId, LoadOp, RenderPass, RenderPassDesc, StoreOp};

use super::draw::DrawSource;
use super::pass::{OpenPass, PassAspect, defined_index};
use super::{Context, Fallible};
use crate::call::{Filter, Wrap};
use crate::program::{ProgramTexture, SamplerState, TextureSnapshot, blit_pipeline, clear_pipeline};
use crate::report::{AttachmentRecord, DrawRecord, EndCause, LoadKind, PassCost, PassRecord, Role, Slot, StoreKind};

/// What a core texture was built from, besides its texels.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) struct BuiltKey {
    width: u32,
    height: u32,
    color_space: tiler::ColorSpace,
    mip_chain: tiler::MipChain,
    encoded: Option<tiler::TexelFormat>,
}

/// A core texture kept across submissions with the version of the image it was built from
/// (the image may be drawn into or written after: its version then changes).
pub(crate) struct BuiltTexture {
    key: BuiltKey,
    version: u64,
    texture: Arc<tiler::Texture>,
}

impl Context {
    /// Ends the open pass: renders it if it has work, and keeps the books.
    pub(crate) fn end_open_pass(&mut self, cause: EndCause) -> Fallible {
        if cause != EndCause::EndPass {
            let what = match cause {
                EndCause::Bind => "binding another framebuffer",
                EndCause::Swap => "swap_buffers",
                EndCause::EndTiling => "end_tiling",
                EndCause::Copy => "copy_tex_sub_image",
                EndCause::End => super::explicit::END_OF_TRACE,
                EndCause::Flush { flush } => flush.describe(),
                EndCause::EndPass => unreachable!(),
            };
            self.outside_explicit_pass(what)?;
        }
        let Some(mut pass) = self.pass.take() else { return Ok(()) };
        let here = self.here;
        if cause == EndCause::Swap && pass.framebuffer == 0 && pass.copy_texture.is_none() {
            for a in pass.aspects.iter_mut() {
                if matches!(a.slot, Slot::Depth | Slot::Stencil)
                    && a.role == Role::Attached
                    && a.store == StoreKind::Store
                {
                    a.store = StoreKind::DontCare;
                    a.store_reason = "the window's depth and stencil are undefined after a swap (EGL)".to_string();
                }
            }
        }
        if let EndCause::Flush { .. } = cause {
            // The rest of the pass needs the samples: a flush keeps them.
            for a in pass.aspects.iter_mut() {
                if a.resolve.is_some() && !a.invalidated && !a.transient && a.store == StoreKind::DontCare {
                    a.store = StoreKind::Store;
                    a.store_reason = "the samples are kept for the rest of the pass, cut by a flush".to_string();
                }
            }
        }
        let full_area = pass.region.is_none_or(|r| r.area() == pass.targets.width as u64 * pass.targets.height as u64);
        if !pass.has_work() {
            // Nothing to render; what was invalidated is undefined from now on.
            for a in &pass.aspects {
                if a.invalidated && full_area {
                    self.undefine(a.image, a.slot, "invalidated");
                }
            }
            self.release(pass);
            return Ok(());
        }

        // The explicit render pass.
        let load_color = |a: &PassAspect| match a.load {
            LoadKind::Load => LoadOp::Load,
            LoadKind::Clear => LoadOp::Clear(a.clear),
            LoadKind::DontCare => LoadOp::DontCare,
        };
        let store = |a: &PassAspect| match a.store {
            StoreKind::Store => StoreOp::Store,
            StoreKind::DontCare => StoreOp::DontCare,
        };
        let color = pass
            .aspects
            .iter()
            .filter(|a| matches!(a.slot, Slot::Color(_)))
            .map(|a| ColorAttachment {
                image: a.image,
                load: load_color(a),
                store: store(a),
                resolve: a.resolve.filter(|_| !a.invalidated),
            })
            .collect();
        let depth_stencil = pass.targets.depth_stencil.map(|ds| {
            let find = |slot| pass.aspects.iter().find(|a| a.slot == slot);
            let (depth_load, depth_store) = match find(Slot::Depth) {
                Some(a) => (load_color(a).map(|c| c[0]), store(a)),
                None => (LoadOp::DontCare, StoreOp::DontCare),
            };
            let (stencil_load, stencil_store) = match find(Slot::Stencil) {
                Some(a) => (load_color(a).map(|c| c[0] as u8), store(a)),
                None => (LoadOp::DontCare, StoreOp::DontCare),
            };
            DepthStencilAttachment { image: ds.image, depth_load, depth_store, stencil_load, stencil_store }
        });
        let mut snapshots: HashMap<ImageId, Arc<TextureSnapshot>> = HashMap::new();
        let mut textures: HashMap<ImageId, Arc<tiler::Texture>> = HashMap::new();
        let mut draws = Vec::with_capacity(pass.draws.len());
        let mut extra = tiler::Ledger::default();
        for d in &pass.draws {
            let pipeline = match &d.source {
                DrawSource::Program { program, textures: sampled, instance_fetch_bytes } => {
                    extra.add(tiler::Category::VertexFetch, *instance_fetch_bytes);
                    self.program_draw_pipeline(
                        program,
                        sampled,
                        &mut snapshots,
                        &mut textures,
                        pass.targets.height,
                        d.desc.clone(),
                    )?
                }
                DrawSource::Clear { color, depth, targets } => clear_pipeline(*color, *depth, *targets, d.desc.clone()),
                DrawSource::Rectangle { image, ndc, tex, sampler, read_bytes, alpha_one } => {
                    extra.add(tiler::Category::TextureFetch, *read_bytes);
                    let mut snapshot = self.snapshot(&mut snapshots, *image)?;
                    if *alpha_one {
                        snapshot = Arc::new(snapshot.with_alpha_one());
                    }
                    blit_pipeline(*ndc, *tex, snapshot, *sampler, d.desc.clone())
                }
            }
            .map_err(|e| format!("draw recorded at {}: {e}", d.call))?;
            draws.push(Draw {
                pipeline,
                vertex_buffers: d.vertex_buffers.clone(),
                index_buffer: d.index,
                first: d.first,
                count: d.count,
                vertex_offset: 0,
                viewport: Some(d.viewport),
                scissor: d.scissor,
            });
        }
        let desc = RenderPassDesc { color, depth_stencil, render_area: pass.region };
        let mut render_pass = match &pass.explicit {
            Some(e) => {
                let mut p = RenderPass::with_subpasses(desc, e.subpasses.clone(), e.dependencies.clone());
                p.subpass_starts = e.starts.clone();
                p
            }
            None => RenderPass::new(desc),
        };
        render_pass.draws = draws;
        // GL's framebuffer objects are rendered y up into images stored top row first, so
        // their samples lie where llvmpipe's do only mirrored (`SampleOrigin`); the window is
        // stored top row first by both.
        if pass.framebuffer != 0 {
            render_pass = render_pass.with_sample_origin(tiler::SampleOrigin::LowerLeft);
        }
        let report = match self.device.submit(&render_pass) {
            Ok(report) => report,
            Err(e) => {
                let at = match &e {
                    tiler::Error::Draw { draw, .. }
                    | tiler::Error::IndexOutOfRange { draw, .. }
                    | tiler::Error::NonFinitePosition { draw, .. } => {
                        pass.draws.get(*draw).map(|d| format!(" (the draw recorded at {})", d.call))
                    }
                    _ => None,
                };
                let what = match pass.copy_texture {
                    Some(t) => format!("the copy into texture {t}"),
                    None => format!("the render pass of framebuffer {} begun at {}", pass.framebuffer, pass.started_at),
                };
                self.release(pass);
                return Err(format!("{what} could not be rendered{}: {e}", at.unwrap_or_default()));
            }
        };

        // The books: queries, what was read and written, and the pass record.
        let index = self.passes_rendered;
        self.passes_rendered += 1;
        let frame = here.frame;
        self.last_submit_frame = Some(frame);
        for (d, stats) in pass.draws.iter().zip(&report.draws) {
            if let Some(q) = d.query.and_then(|q| self.queries.get_mut(&q)) {
                q.samples += stats.samples_passed;
                q.pending_draws = q.pending_draws.saturating_sub(1);
                q.last_frame = q.last_frame.max(frame);
            }
        }
        // The pixels the core covered: the tiled-rendering region, or a scissor box every
        // draw lies inside (tiles outside it were neither loaded nor stored).
        let area = match report.render_area {
            Some(r) => r.area(),
            None => pass.targets.width as u64 * pass.targets.height as u64,
        };
        let full_area = report.render_area.is_none();
        let samples = pass.targets.samples as u64;
        let mut attachments = Vec::new();
        for a in &pass.aspects {
            let info = &self.images[&a.image];
            let format = info.desc.format;
            // A packed depth-stencil sample moves as one word: an aspect loaded (or stored)
            // without the other costs the whole word (`Format::depth_access_bytes`).
            let partner = |moves: &dyn Fn(&PassAspect) -> bool| {
                let other = match a.slot {
                    Slot::Depth => Slot::Stencil,
                    Slot::Stencil => Slot::Depth,
                    Slot::Color(_) => return false,
                };
                pass.aspects.iter().any(|b| b.image == a.image && b.slot == other && moves(b))
            };
            let aspect_bytes = |with_other: bool| {
                (match a.slot {
                    Slot::Color(_) => format.bytes_per_sample(),
                    Slot::Depth => format.depth_access_bytes(with_other),
                    Slot::Stencil => format.stencil_access_bytes(with_other),
                }) as u64
            };
            let load_bytes = area * samples * aspect_bytes(partner(&|b| b.load == LoadKind::Load));
            let bytes = area * samples * aspect_bytes(partner(&|b| b.store == StoreKind::Store));
            let gl_format = info.gl_format;
            if a.load == LoadKind::Load {
                self.consume(a.image, a.slot);
            }
            match a.store {
                StoreKind::Store => {
                    let info = self.images.get_mut(&a.image).expect("attached image");
                    info.defined[defined_index(a.slot)] = true;
                    info.last_write = Some(frame);
                    self.register_store(a.image, a.slot, index, bytes, full_area);
                }
                StoreKind::DontCare if a.role == Role::Attached && full_area => {
                    self.undefine(a.image, a.slot, &format!("not stored by pass {index}"));
                }
                StoreKind::DontCare => {}
            }
            let mut resolve_bytes = 0;
            if let Some(resolve) = a.resolve.filter(|_| !a.invalidated) {
                let d = self.images[&resolve].desc;
                resolve_bytes = area * d.format.bytes_per_sample() as u64;
                let info = self.images.get_mut(&resolve).expect("resolve image");
                info.defined[0] = true;
                info.last_write = Some(frame);
                self.register_store(resolve, Slot::Color(0), index, resolve_bytes, full_area);
            }
            attachments.push(AttachmentRecord {
                slot: a.slot,
                image: a.image,
                format,
                gl_format,
                samples: pass.targets.samples,
                role: a.role,
                load: a.load,
                load_reason: a.load_reason.clone(),
                store: a.store,
                store_reason: a.store_reason.clone(),
                load_bytes: if a.load == LoadKind::Load { load_bytes } else { 0 },
                store_bytes: if a.store == StoreKind::Store { bytes } else { 0 },
                resolve: a.resolve.filter(|_| !a.invalidated),
                resolve_bytes,
            });
        }
        let draws = pass
            .draws
            .iter()
            .zip(&report.draws)
            .map(|(d, stats)| DrawRecord {
                call: d.call,
                kind: d.kind,
                program: match &d.source {
                    DrawSource::Program { program, .. } => program.kind(),
                    _ => None,
                },
                clip_rect: d.clip_rect,
                blend: d.desc.color_targets.iter().any(|t| t.blend.is_some()),
                depth_test: d.desc.depth_stencil.depth_test,
                depth_write: d.desc.depth_stencil.depth_write,
                discards: match &d.source {
                    DrawSource::Program { program, .. } => program.discards(),
                    _ => false,
                },
                texture_bytes: match &d.source {
                    DrawSource::Rectangle { read_bytes, .. } => *read_bytes,
                    _ => 0,
                },
                sampled: match &d.source {
                    DrawSource::Program { textures, .. } => textures.first().map(|t| t.image),
                    DrawSource::Rectangle { image, .. } => Some(*image),
                    DrawSource::Clear { .. } => None,
                },
                stats: *stats,
                partial_clear: d.partial_clear.clone(),
            })
            .collect();
        let record = PassRecord {
            index,
            frame,
            framebuffer: pass.framebuffer,
            copy_texture: pass.copy_texture,
            window_preserved: pass.window_preserved,
            width: pass.targets.width,
            height: pass.targets.height,
            samples: pass.targets.samples,
            render_area: report.render_area,
            start: pass.start,
            started_at: pass.started_at,
            end: cause,
            ended_at: here,
            attachments,
            subpasses: render_pass.subpasses.clone(),
            dependencies: render_pass.dependencies.clone(),
            draw_subpasses: if pass.explicit.is_some() {
                (0..pass.draws.len()).map(|i| render_pass.subpass_of(i) as u32).collect()
            } else {
                Vec::new()
            },
            draws,
            reads: {
                let mut reads: Vec<ImageId> = pass.images_sampled.iter().copied().collect();
                reads.sort_unstable();
                reads
            },
            dropped: std::mem::take(&mut pass.dropped),
            cost: PassCost::from(&report),
            extra,
            core: self.config.keep_pass_reports.then(|| Box::new(report)),
        };
        self.frame.passes.push(record);
        self.release(pass);
        self.retire_depth_snapshots(snapshots);
        Ok(())
    }

    /// Keeps the depth snapshots of a submitted pass, whose buffers [`Context::spare_depths`]
    /// reuses once nothing else holds them (the device may still be rendering the pass).
    fn retire_depth_snapshots(&self, snapshots: HashMap<ImageId, Arc<TextureSnapshot>>) {
        /// Snapshots kept, at most: the newest, a few passes' worth.
        const KEPT: usize = 4;
        let mut retired = self.retired_depths.lock().unwrap_or_else(|e| e.into_inner());
        retired.extend(snapshots.into_values().filter(|s| s.is_depth()));
        let excess = retired.len().saturating_sub(KEPT);
        retired.drain(..excess);
    }

    /// The depths of a retired depth snapshot nothing holds any more, to be filled again.
    fn spare_depths(&self) -> Option<Vec<f32>> {
        let mut retired = self.retired_depths.lock().unwrap_or_else(|e| e.into_inner());
        let free = retired.iter().position(|s| Arc::strong_count(s) == 1 && Arc::weak_count(s) == 0)?;
        Arc::into_inner(retired.remove(free)).and_then(TextureSnapshot::into_depths)
    }

    /// Frees what a finished pass held on to.
    fn release(&mut self, pass: OpenPass) {
        for (buffer, len) in pass.retired_buffers {
            self.free_buffer(buffer, len);
        }
        for image in pass.retired_images {
            self.free_image(image);
        }
    }

    /// What a textured draw samples: RGBA8 images through the core's sampler, others through
    /// a snapshot; each texture made once per submission. An incomplete texture reads
    /// (0, 0, 0, 1) and no memory.
    pub(crate) fn program_texture(
        &self,
        snapshots: &mut HashMap<ImageId, Arc<TextureSnapshot>>,
        textures: &mut HashMap<ImageId, Arc<tiler::Texture>>,
        image: ImageId,
        sampler: SamplerState,
        mipmaps: bool,
    ) -> Fallible<ProgramTexture> {
        if sampler.incomplete(mipmaps) {
            return Ok(ProgramTexture::Snapshot(Arc::new(TextureSnapshot::constant([0.0, 0.0, 0.0, 1.0])), sampler));
        }
        let d = self.images[&image].desc;
        if d.format.is_integer() {
            return Err(format!("{image} ({}) is an integer texture: only isampler/usampler read it", d.format));
        }
        // RGBA8 as it is; RGB565 and float images (with every value in [0, 1], which 8 bits
        // hold) decoded, modelled in their own format; others (HDR floats, depth) snapshots.
        let (color_space, own_format) = match d.format {
            tiler::Format::Rgba8Unorm => (tiler::ColorSpace::Linear, None),
            tiler::Format::Rgba8UnormSrgb => (tiler::ColorSpace::Srgb, None),
            // Made once per submission: one already made is taken as it is.
            _ if d.samples == 1 && textures.contains_key(&image) => (tiler::ColorSpace::Linear, None),
            format if d.samples == 1 => {
                let data = self.device.image_data(image).map_err(|e| e.to_string())?;
                match sampled_format(format, data) {
                    Some(own) => (tiler::ColorSpace::Linear, Some(own)),
                    None => return Ok(ProgramTexture::Snapshot(self.snapshot(snapshots, image)?, sampler)),
                }
            }
            _ => return Ok(ProgramTexture::Snapshot(self.snapshot(snapshots, image)?, sampler)),
        };
        if d.samples != 1 {
            return Ok(ProgramTexture::Snapshot(self.snapshot(snapshots, image)?, sampler));
        }
        let mip_chain = if mipmaps { tiler::MipChain::Linear } else { tiler::MipChain::BaseOnly };
        let texture = match textures.get(&image) {
            Some(t) => t.clone(),
            None if own_format.is_some() => {
                let own = own_format.expect("matched");
                let data = self.device.image_data(image).map_err(|e| e.to_string())?;
                let t = tiler::Texture::from_encoded(own, d.width, d.height, data, color_space, mip_chain)
                    .map_err(|e| e.to_string())?;
                let t = Arc::new(t);
                textures.insert(image, t.clone());
                t
            }
            None => {
                let data = self.device.image_data(image).map_err(|e| e.to_string())?;
                if let Some(t) = self.unorm16_texture(image, data, mip_chain)? {
                    let t = Arc::new(t);
                    textures.insert(image, t.clone());
                    return Ok(ProgramTexture::Core(t, core_sampler(sampler, mipmaps)));
                }
                // Levels given by the application, when they are the whole chain.
                let given = self
                    .textures
                    .values()
                    .find(|t| t.image == image)
                    .and_then(|t| t.given_chain(d.width, d.height))
                    .filter(|_| mipmaps);
                let encoded = self.encoded_format(image);
                let key = BuiltKey { width: d.width, height: d.height, color_space, mip_chain, encoded };
                let t = match given {
                    Some(levels) => {
                        let chain: Vec<&[u8]> =
                            std::iter::once(data).chain(levels.iter().map(|l| l.as_slice())).collect();
                        let t = tiler::Texture::from_rgba8_levels(d.width, d.height, &chain, color_space)
                            .and_then(|t| match encoded {
                                Some(format) => t.stored_as(format),
                                None => Ok(t),
                            })
                            .map_err(|e| e.to_string())?;
                        Arc::new(t)
                    }
                    None => self.built_texture(image, key, data)?,
                };
                textures.insert(image, t.clone());
                t
            }
        };
        Ok(ProgramTexture::Core(texture, core_sampler(sampler, mipmaps)))
    }

    /// The texture of RGBA8 `data` of `image` as `key` says: the one built for an earlier
    /// submission while the image keeps its version ([`tiler::Device::image_version`]: a
    /// texture sampled by pass after pass, as a window's picture is, is built once), else a
    /// new one, kept for the next. A texture is a function of its texels and `key` alone; only
    /// its id differs, and ids only tell textures apart within a pass's texture-cache model.
    fn built_texture(&self, image: ImageId, key: BuiltKey, data: &[u8]) -> Fallible<Arc<tiler::Texture>> {
        let version = self.device.image_version(image).map_err(|e| e.to_string())?;
        let mut built = self.built_textures.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(b) = built.get(&image)
            && (b.key, b.version) == (key, version)
        {
            return Ok(b.texture.clone());
        }
        // The texture this replaces, when no pass holds it any more: the new one is built in
        // its memory (a render target sampled each frame is built each frame).
        let old = built.remove(&image).and_then(|b| Arc::into_inner(b.texture));
        // Built on the device's threads, which wait for this pass.
        let (width, height, color_space, mips) = (key.width, key.height, key.color_space, key.mip_chain);
        let t = self
            .device
            .install(|| match old {
                Some(old) => tiler::Texture::from_rgba8_replacing(width, height, data, color_space, mips, old),
                None => tiler::Texture::from_rgba8(width, height, data, color_space, mips),
            })
            .and_then(|t| match key.encoded {
                Some(format) => t.stored_as(format),
                None => Ok(t),
            })
            .map_err(|e| e.to_string())?;
        let texture = Arc::new(t);
        built.insert(image, BuiltTexture { key, version, texture: texture.clone() });
        Ok(texture)
    }

    /// Drops the texture kept for `image`, whose storage is released.
    pub(crate) fn forget_built_texture(&mut self, image: ImageId) {
        self.built_textures.get_mut().unwrap_or_else(|e| e.into_inner()).remove(&image);
    }

    /// The decoded texels of an image, once per submission.
    pub(crate) fn snapshot(
        &self,
        cache: &mut HashMap<ImageId, Arc<TextureSnapshot>>,
        image: ImageId,
    ) -> Fallible<Arc<TextureSnapshot>> {
        if let Some(s) = cache.get(&image) {
            return Ok(s.clone());
        }
        let d = self.images[&image].desc;
        let snapshot = if d.format.is_color() {
            let data = self.device.image_data(image).map_err(|e| e.to_string())?.to_vec();
            Arc::new(TextureSnapshot::color(d.width, d.height, d.format, d.samples, data))
        } else {
            let mut depths = self.spare_depths().unwrap_or_default();
            self.device.read_depth_into(image, &mut depths).map_err(|e| e.to_string())?;
            let fixed_point = d.format != tiler::Format::D32Float;
            Arc::new(TextureSnapshot::depth(d.width, d.height, depths, fixed_point))
        };
        cache.insert(image, snapshot.clone());
        Ok(snapshot)
    }
}

/// The core's sampler for a GL sampling state; `mipmaps`: the texture has a mip chain (a
/// mipmap filter reads it).
pub(crate) fn core_sampler(sampler: SamplerState, mipmaps: bool) -> tiler::Sampler {
    let core_filter = |f: Filter| match f.base() {
        Filter::Nearest => tiler::Filter::Nearest,
        _ => tiler::Filter::Linear,
    };
    let mipmap = match sampler.min_filter.mipmap().filter(|_| mipmaps) {
        None => tiler::MipmapMode::None,
        Some(Filter::Nearest) => tiler::MipmapMode::Nearest,
        Some(_) => tiler::MipmapMode::Linear,
    };
    let core_wrap = |w: Wrap| match w {
        Wrap::ClampToEdge => tiler::Wrap::ClampToEdge,
        Wrap::Repeat => tiler::Wrap::Repeat,
        Wrap::MirroredRepeat => tiler::Wrap::MirroredRepeat,
    };
    tiler::Sampler {
        mag_filter: core_filter(sampler.mag_filter),
        min_filter: core_filter(sampler.min_filter),
        mipmap,
        wrap_u: core_wrap(sampler.wrap_s),
        wrap_v: core_wrap(sampler.wrap_t),
        // GL's default `WRAP_R`; a 3-D texture's own is set where it is bound.
        wrap_w: tiler::Wrap::Repeat,
        lod_bias: 0.0,
    }
}

/// The core format an image of `format` other than RGBA8 is sampled from: RGB565, and float
/// formats whose every value is within `[0, 1]` (the core sampler filters 8-bit texels, which
/// hold them; others keep the snapshot's float precision, uncounted).
fn sampled_format(format: tiler::Format, data: &[u8]) -> Option<tiler::TexelFormat> {
    use tiler::{Format, TexelFormat};
    let in_range = |v: f32| (0.0..=1.0).contains(&v);
    match format {
        Format::Rgb565Unorm => Some(TexelFormat::Rgb565),
        Format::Rgba16Float => data
            .chunks_exact(2)
            .all(|h| in_range(half::f16::from_le_bytes([h[0], h[1]]).to_f32()))
            .then_some(TexelFormat::Rgba16Float),
        Format::Rgba32Float | Format::R32Float => data
            .chunks_exact(4)
            .all(|f| in_range(f32::from_le_bytes([f[0], f[1], f[2], f[3]])))
            .then_some(if format == Format::R32Float { TexelFormat::R32Float } else { TexelFormat::Rgba32Float }),
        _ => None,
    }
}

trait MapLoad<T> {
    fn map<U>(self, f: impl FnOnce(T) -> U) -> LoadOp<U>;
}

impl<T> MapLoad<T> for LoadOp<T> {
    fn map<U>(self, f: impl FnOnce(T) -> U) -> LoadOp<U> {
        match self {
            LoadOp::Load => LoadOp::Load,
            LoadOp::Clear(v) => LoadOp::Clear(f(v)),
            LoadOp::DontCare => LoadOp::DontCare,
        }
    }
}
