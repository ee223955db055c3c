//! `tiler diff`: compares two PNGs the way tiler's pictures are held against llvmpipe's
//! (`../shared/reference/README.md`): the share of pixels whose every channel is within a
//! tolerance, and a difference image to look at.

use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::Args;
use tiler_scene::compare::{REFERENCE_MIN_FRACTION, REFERENCE_TOLERANCE, compare_rgba8, read_png};

#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The picture to check.
    pub ours: PathBuf,

    /// The reference picture (same size).
    pub reference: PathBuf,

    /// Largest difference per channel, out of 255, for a pixel to count as matching.
    #[arg(long, default_value_t = REFERENCE_TOLERANCE)]
    pub tolerance: u8,

    /// The share of pixels, 0 to 1, that must match.
    #[arg(long, default_value_t = REFERENCE_MIN_FRACTION)]
    pub min_fraction: f64,

    /// Write the difference image here (matching pixels a dim grey copy of the reference, the
    /// others red, brighter the larger the difference).
    #[arg(long)]
    pub out: Option<PathBuf>,

    /// Compare colour only: alpha is taken as opaque in both pictures. For a replayed capture's
    /// frames against `eglretrace` snapshots, which are RGB (the window's alpha is whatever the
    /// application wrote, and no display shows it).
    #[arg(long)]
    pub color_only: bool,
}

/// Prints the comparison; fails (exit status 1) when too few pixels match.
pub fn run(args: &DiffArgs) -> Result<()> {
    if !(0.0..=1.0).contains(&args.min_fraction) {
        bail!("--min-fraction must be between 0 and 1, not {}", args.min_fraction);
    }
    if let Some(out) = &args.out {
        crate::files::check_png("--out", out, &[args.ours.clone(), args.reference.clone()])?;
    }
    let (width, height, mut ours) = read_png(&args.ours).map_err(|e| anyhow!(e))?;
    let (rw, rh, mut reference) = read_png(&args.reference).map_err(|e| anyhow!(e))?;
    if args.color_only {
        for picture in [&mut ours, &mut reference] {
            picture.iter_mut().skip(3).step_by(4).for_each(|alpha| *alpha = 255);
        }
    }
    if (width, height) != (rw, rh) {
        bail!("{} is {width}×{height} but {} is {rw}×{rh}", args.ours.display(), args.reference.display());
    }
    let c = compare_rgba8(&ours, &reference, width, height, args.tolerance);
    println!(
        "{:.3}% of pixels within {}/255 per channel (largest difference {}): {}",
        100.0 * c.fraction_within(),
        args.tolerance,
        c.max_difference,
        if c.passes(args.min_fraction) { "match" } else { "DIFFERENT" }
    );
    if let Some(out) = &args.out {
        crate::files::write_png(out, width, height, &c.difference_image)?;
    }
    if !c.passes(args.min_fraction) {
        bail!(
            "{} differs from {}: fewer than {:.1}% of pixels within tolerance",
            args.ours.display(),
            args.reference.display(),
            100.0 * args.min_fraction
        );
    }
    Ok(())
}
