//! `clothbake export`: a fabric's best stock material for an engine, written in its file,
//! with what it loses printed (and stated in the file).

use super::CommandResult;
use clothbake::export::loss::{FabricReference, LOSS_PAIRS, Loss};
use clothbake::export::{TARGETS, export, target};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::scene::Scene;
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args)]
#[command(after_help = targets_help())]
pub struct Args {
    /// The fabric to export (a built-in one, or one of --fabrics).
    fabric: String,
    /// The engine whose file to write (TARGETS, below).
    #[arg(long, value_parser = target_name)]
    to: String,
    /// The file to write (written atomically: on any error no file is left).
    #[arg(long)]
    out: PathBuf,
    /// Fabric file (TOML) to take the fabric from instead of the built-in fabrics (a
    /// `clothbake weave` or `clothbake fit` output exports the same way).
    #[arg(long)]
    fabrics: Option<PathBuf>,
}

/// The targets of `--to`, from the registry: the word, the file's extension and the model
/// the file holds.
fn targets_help() -> String {
    let rows: Vec<String> = TARGETS
        .iter()
        .map(|t| format!("  {:<10} .{:<5} {}", t.name, t.extension, t.model.title))
        .collect();
    format!("TARGETS:\n{}", rows.join("\n"))
}

fn target_name(name: &str) -> Result<String, String> {
    target(name)
        .map(|t| t.name.to_string())
        .map_err(|e| e.to_string())
}

pub fn run(args: Args) -> CommandResult {
    let set = FabricSet::load_or_builtin(args.fabrics.as_deref())?;
    let fabric = set.require(&args.fabric)?.clone();
    let target = target(&args.to)?;
    // Refuse a missing directory before the fit, not after it.
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty())
        && !parent.is_dir()
    {
        let message = format!(
            "cannot write {}: no directory {}",
            args.out.display(),
            parent.display()
        );
        return Err(message.into());
    }
    let scene = Scene::builtin();
    let start = Instant::now();
    let reference = FabricReference::new(&fabric);
    let images = drape::reference(&scene, &fabric)?;
    let measure = |material: &_| {
        let mut loss = reference.measure(material);
        loss.image = drape::measure(images.as_ref(), material);
        loss
    };
    let done = export(target, &fabric, &scene, &args.out, &measure)?;
    println!(
        "{} → {} ({}): {} parameters fitted in {:.1} s ({} evaluations of F)",
        fabric.name,
        target.name,
        target.model.title,
        target.model.parameters.len(),
        start.elapsed().as_secs_f64(),
        done.fit.evaluations,
    );
    for (p, v) in target
        .model
        .parameters
        .iter()
        .zip(&done.fit.material.values)
    {
        println!("  {:<34} {v:.4}", p.name);
    }
    print_loss(&done.loss);
    println!("wrote {} ({} bytes)", done.path.display(), done.bytes);
    Ok(())
}

fn print_loss(loss: &Loss) {
    println!("what it loses against the fabric:");
    println!(
        "  relative RMS of F: {:.4} on uniform pairs, {:.4} on highlight pairs ({LOSS_PAIRS} each, against the direct evaluation)",
        loss.uniform.relative_rms, loss.highlight.relative_rms
    );
    println!(
        "  directional albedo: up to {:.1}% off (at {}° elevation), {:.1}% RMS over elevations",
        100.0 * loss.albedo.largest_relative,
        loss.albedo.at_elevation_deg,
        100.0 * loss.albedo.rms_relative
    );
    match loss.image {
        Some(image) => println!(
            "  drape image (the default scene's camera and lights, no environment): relative L2 {:.4}, PSNR {:.1} dB",
            image.relative_l2, image.psnr_db
        ),
        None => println!("  drape image: not measured (built without the runtime)"),
    }
}

/// The drape's image error, with the runtime; nothing without it.
#[cfg(feature = "runtime")]
mod drape {
    use clothbake::evaluator::stock::StockMaterial;
    use clothbake::export::loss::ImageLoss;
    use clothbake::gpu::GpuContext;
    use clothbake::model::Fabric;
    use clothbake::render::drape_loss::DrapeReference;
    use clothbake::scene::Scene;
    use clothbake::scene::mesh::Mesh;

    pub fn reference(
        scene: &Scene,
        fabric: &Fabric,
    ) -> Result<Option<DrapeReference>, Box<dyn std::error::Error>> {
        let context = GpuContext::new()?;
        let mesh = Mesh::from_spec(&scene.mesh)?;
        Ok(Some(DrapeReference::new(&context, scene, &mesh, fabric)?))
    }

    pub fn measure(
        reference: Option<&DrapeReference>,
        material: &StockMaterial,
    ) -> Option<ImageLoss> {
        reference.map(|r| r.measure(material))
    }
}

#[cfg(not(feature = "runtime"))]
mod drape {
    use clothbake::evaluator::stock::StockMaterial;
    use clothbake::export::loss::ImageLoss;
    use clothbake::model::Fabric;
    use clothbake::scene::Scene;

    /// Nothing to rasterise with.
    pub enum DrapeReference {}

    pub fn reference(
        _: &Scene,
        _: &Fabric,
    ) -> Result<Option<DrapeReference>, Box<dyn std::error::Error>> {
        Ok(None)
    }

    pub fn measure(_: Option<&DrapeReference>, _: &StockMaterial) -> Option<ImageLoss> {
        None
    }
}
