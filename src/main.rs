//! The clothbake command line: parses arguments and dispatches to the library.

use clap::{Parser, Subcommand};
use clothbake::accuracy::measure;
use clothbake::bake_job::{self, BakeJob, Outcome, ResolutionChoice};
#[cfg(feature = "runtime")]
use clothbake::environment::EnvironmentSource;
use clothbake::eval_stream::{EvalOutput, SampleOutput, eval_stream, sample_stream};
use clothbake::fabric_file::FabricSet;
use clothbake::manifest;
use clothbake::model::{Fabric, Integration, Patch, ResonantNodes};
#[cfg(feature = "runtime")]
use clothbake::render;
use clothbake::sampling::{Sampler, albedo_curve, describe_albedo};
#[cfg(feature = "runtime")]
use clothbake::scene::MAX_ENVIRONMENT_SAMPLES;
use clothbake::scene::Scene;
use clothbake::table::Layout;
use clothbake::table::shader_language::{ShaderLanguage, lookup_shader};
use clothbake::table::wgsl::LookupShaderOptions;
use clothbake::table_file::read_table;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    version,
    about = "Bake the Sadeghi et al. 2013 cloth model into lookup tables"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the fabrics and their key parameters.
    Fabrics {
        /// Fabric file (TOML) to use instead of the built-in fabrics.
        #[arg(long)]
        fabrics: Option<PathBuf>,
    },
    /// Evaluate F(wi, wo): JSON lines {"wi":[x,y,z],"wo":[x,y,z]} on stdin, {"f":[r,g,b]} out.
    Eval {
        /// Fabric name.
        #[arg(long)]
        fabric: String,
        /// How F is evaluated: the converged direct rule (default unless --samples is given),
        /// paper mode (--samples N strata per thread), or the resonant quadrature.
        #[arg(long, value_enum)]
        integration: Option<IntegrationArg>,
        /// Paper mode: N stratified samples per thread (alone, it selects paper mode).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
        samples: Option<u32>,
        #[command(flatten)]
        nodes: NodeArgs,
        /// Fabric file (TOML) to use instead of the built-in fabrics.
        #[arg(long)]
        fabrics: Option<PathBuf>,
        /// Also look each pair up in this table and print it as "table":[r,g,b].
        #[arg(long)]
        table: Option<PathBuf>,
        /// Also print the fabric sampler's density of wi given wo as "pdf":p (the density
        /// `sample` draws with).
        #[arg(long)]
        pdf: bool,
    },
    /// Importance-sample F: JSON lines {"wo":[x,y,z],"u":[u1,u2,u3]} (u in [0, 1)) on stdin,
    /// {"wi":[x,y,z],"pdf":p,"weight":[r,g,b]} out (weight = F/pdf; "wi":null when rejected).
    Sample {
        /// Fabric name.
        #[arg(long)]
        fabric: String,
        /// Fabric file (TOML) to use instead of the built-in fabrics.
        #[arg(long)]
        fabrics: Option<PathBuf>,
        /// F from this table's lookup instead of the direct evaluation.
        #[arg(long)]
        table: Option<PathBuf>,
    },
    /// Print each fabric's directional albedo ∫F dwi over outgoing elevation, and its maximum.
    Albedo {
        /// Fabric names (default: every fabric).
        #[arg(long, num_args = 1.., conflicts_with = "table")]
        fabric: Vec<String>,
        /// Fabric file (TOML) to use instead of the built-in fabrics.
        #[arg(long)]
        fabrics: Option<PathBuf>,
        /// F from this table's lookup (its own fabric) instead of the direct evaluation.
        #[arg(long)]
        table: Option<PathBuf>,
        /// Importance samples per outgoing direction.
        #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(16..=1_000_000))]
        samples: u32,
    },
    /// Bake fabrics into EXR tables (by default the built-in six into tables/).
    Bake {
        /// Fabrics to bake (default: every fabric in the fabric file).
        #[arg(long, num_args = 1.., conflicts_with = "scene")]
        fabric: Vec<String>,
        /// Scene file (TOML): bake only the fabrics it names, within its budget.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Fabric file (TOML) to use instead of the built-in fabrics.
        #[arg(long)]
        fabrics: Option<PathBuf>,
        /// Table layout (default: the scene's, else thread_frame).
        #[arg(long, value_parser = parse_layout)]
        layout: Option<Layout>,
        /// Layout resolution (default: the layout's own).
        #[arg(long, conflicts_with = "max_error")]
        resolution: Option<u32>,
        /// Choose the smallest resolution whose relative RMS error (uniform and highlight
        /// pairs, against direct evaluation) is at most this, and report it.
        #[arg(long)]
        max_error: Option<f64>,
        /// Output directory.
        #[arg(long, default_value = "tables")]
        out: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
        threads: Option<u32>,
        /// Bake even tables the manifest shows are up to date.
        #[arg(long)]
        force: bool,
    },
    /// Measure a table's error against the direct evaluation of the fabric it records.
    Check {
        /// The table (EXR) to check.
        table: PathBuf,
        /// Uniform and highlight pairs to measure on (each).
        #[arg(long, default_value_t = 20000, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
        pairs: u32,
    },
    /// Print the lookup specialised for a table (`fn cloth_brdf(wi, wo)` and its bindings,
    /// see src/gpu/table.rs), to use the table in another engine: WGSL, or GLSL, HLSL or
    /// MSL translated by naga together with a compute kernel over pairs.
    Wgsl {
        /// The table (EXR).
        table: PathBuf,
        /// Shading language: wgsl, glsl (4.50 core), hlsl (shader model 5.1) or msl (2.4).
        #[arg(long, default_value = "wgsl")]
        lang: ShaderLanguage,
        /// Leave split_frame's horizon band out: pairs within 1° of the horizon read the
        /// table like every other (for software rasterisers, which run the band's resonant
        /// kernel in every pixel).
        #[arg(long)]
        no_horizon_band: bool,
    },
    #[cfg(feature = "runtime")]
    /// Measure speed against error for every fabric (tables of each layout over a range of
    /// resolutions, paper mode at N = 1..64, bake times) and write REPORT.md, report.json
    /// and PNG plots.
    Report {
        /// Fewer resolutions, pairs and repetitions (every fabric still).
        #[arg(long)]
        quick: bool,
        /// Output directory.
        #[arg(long, default_value = "report")]
        out: PathBuf,
    },
    #[cfg(feature = "runtime")]
    /// Render the scene's cloth headless to PNG by table lookup (or the direct shader), print
    /// the adapter and the median GPU time per frame; with --reference compare with the CPU.
    Render {
        #[command(flatten)]
        scene: SceneArgs,
        /// Render only this fabric (default: every fabric of the scene, to OUT-STEM-NAME.png).
        #[arg(long)]
        fabric: Option<String>,
        /// Output PNG.
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value_t = 1024)]
        width: u32,
        #[arg(long, default_value_t = 1024)]
        height: u32,
        /// Timed frames (after one warm-up frame); the median is printed.
        #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=10_000))]
        frames: u32,
        /// How the shader evaluates F.
        #[arg(long, value_enum, default_value_t = RenderShaderArg::Lookup)]
        shader: RenderShaderArg,
        /// Tangent samples per thread of --shader direct (default 32).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
        samples: Option<u32>,
        #[command(flatten)]
        nodes: NodeArgs,
        /// Also render the view on the CPU by direct evaluation: writes STEM-reference.png and
        /// STEM-error.png and prints the image error. Under an environment light, F by the
        /// resonant quadrature and the environment by Monte Carlo (--reference-samples).
        #[arg(long)]
        reference: bool,
        /// Importance samples per pixel of the reference's environment term.
        #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
        reference_samples: u32,
        /// Also write the linear radiance (before exposure and tone mapping) as an OpenEXR
        /// file of f16 RGBA beside each PNG (STEM.exr; alpha 1 on cloth, 0 on background).
        #[arg(long)]
        linear: bool,
        #[command(flatten)]
        lookup: LookupArgs,
    },
    #[cfg(feature = "runtime")]
    /// Open an interactive window showing the scene's cloth shaded by table lookup (or by the
    /// direct shader: key D; the resonant shader: key G). Keys are listed at start.
    View {
        #[command(flatten)]
        scene: SceneArgs,
        /// Fabric shown first (default: the scene's first).
        #[arg(long)]
        fabric: Option<String>,
        /// Draw N frames, print the median frame time and exit.
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
        frames: Option<u32>,
        /// Paper-mode samples per thread of the direct shader (+/- change it).
        #[arg(long, default_value_t = clothbake::gpu::direct::DEFAULT_SAMPLES,
              value_parser = clap::value_parser!(u32).range(1..=1024))]
        samples: u32,
        /// Shading at start: table lookup, the model in the shader (key D toggles), or the
        /// resonant quadrature in the shader (key G toggles).
        #[arg(long, value_enum, default_value_t = ShaderArg::Lookup)]
        shader: ShaderArg,
        #[command(flatten)]
        lookup: LookupArgs,
    },
}

/// How `render` and `view` build a table's lookup shader.
#[cfg(feature = "runtime")]
#[derive(clap::Args)]
struct LookupArgs {
    /// split_frame's horizon band (the resonant quadrature for pairs within 1° of the
    /// horizon): auto leaves it out on a software rasteriser (lavapipe), which runs its
    /// kernel in every pixel, and keeps it on a GPU.
    #[arg(long, value_enum, default_value_t = HorizonBandArg::Auto)]
    horizon_band: HorizonBandArg,
}

#[cfg(feature = "runtime")]
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum HorizonBandArg {
    Auto,
    On,
    Off,
}

#[cfg(feature = "runtime")]
impl LookupArgs {
    /// `LookupShaderOptions::for_adapter`'s choice: `None` for auto.
    fn horizon_band(&self) -> Option<bool> {
        match self.horizon_band {
            HorizonBandArg::Auto => None,
            HorizonBandArg::On => Some(true),
            HorizonBandArg::Off => Some(false),
        }
    }
}

/// What `render` and `view` show: a scene, its tables and optionally a user's mesh.
#[cfg(feature = "runtime")]
#[derive(clap::Args)]
struct SceneArgs {
    /// Scene file (TOML): fabrics, camera, lights, mesh (default: tables/scene.toml's).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Directory of baked tables (NAME.exr).
    #[arg(long, default_value = "tables")]
    tables: PathBuf,
    /// OBJ mesh with UVs to show instead of the scene's (the camera is aimed at it).
    #[arg(long)]
    mesh: Option<PathBuf>,
    /// Environment light: `default` (the built-in studio), `uniform` (radiance 1: the white
    /// furnace), `none`, or an equirectangular .hdr or .exr file (default: the scene's).
    #[arg(long, value_parser = parse_environment)]
    env: Option<EnvironmentSource>,
    /// Filtered importance samples per pixel of the environment light (default: the
    /// scene's, 64 in the built-in scene).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_ENVIRONMENT_SAMPLES as i64))]
    env_samples: Option<u32>,
    /// Switch the scene's lights off (the environment alone).
    #[arg(long)]
    no_lights: bool,
}

#[cfg(feature = "runtime")]
impl SceneArgs {
    /// The scene file's scene, or the built-in default scene, with the environment and
    /// lights the options ask for.
    fn load(&self) -> Result<Scene, String> {
        let mut scene = match &self.scene {
            Some(path) => Scene::load(path).map_err(|e| e.to_string())?,
            None => Scene::builtin(),
        };
        if let Some(source) = &self.env {
            scene.environment.source = source.clone();
        }
        if let Some(samples) = self.env_samples {
            scene.environment.samples = samples;
        }
        if self.no_lights {
            scene.lights.clear();
        }
        Ok(scene)
    }
}

#[cfg(feature = "runtime")]
fn parse_environment(word: &str) -> Result<EnvironmentSource, String> {
    word.parse()
        .map_err(|e: clothbake::environment::EnvironmentError| e.to_string())
}

#[cfg(feature = "runtime")]
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum ShaderArg {
    Lookup,
    Direct,
    Resonant,
}

#[cfg(feature = "runtime")]
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum RenderShaderArg {
    /// Table lookup from the baked tables.
    Lookup,
    /// The model itself in the shader (paper mode, --samples per thread).
    Direct,
    /// The resonant quadrature in the shader (--surface-nodes, --volume-nodes, --base-nodes).
    Resonant,
    /// F = 1/π: the frame's cost without BRDF work, the floor under any shader's time.
    Constant,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum IntegrationArg {
    /// The converged direct rule, the ground truth.
    Direct,
    /// Paper mode: --samples N stratified samples per thread (default 32).
    Paper,
    /// The resonant quadrature (--surface-nodes, --volume-nodes, --base-nodes).
    Resonant,
}

/// The resonant quadrature's node counts (`eval --integration resonant`,
/// `render --shader resonant`); each defaults to `ResonantNodes::DEFAULT`'s.
#[derive(clap::Args)]
struct NodeArgs {
    /// Resonant quadrature: Gauss–Legendre nodes per curve segment on the surface lobe.
    #[arg(long, value_parser = resonant_count)]
    surface_nodes: Option<u32>,
    /// Resonant quadrature: nodes per segment on the volume lobe.
    #[arg(long, value_parser = resonant_count)]
    volume_nodes: Option<u32>,
    /// Resonant quadrature: nodes per segment for ⟨P⟩ and the kd term.
    #[arg(long, value_parser = resonant_count)]
    base_nodes: Option<u32>,
}

impl NodeArgs {
    /// The node counts, or an error naming `selector` when any is given but `selected` is
    /// false (the options belong to the resonant rule only).
    fn nodes(&self, selected: bool, selector: &str) -> Result<ResonantNodes, String> {
        let given = [self.surface_nodes, self.volume_nodes, self.base_nodes];
        if !selected && given.iter().any(Option::is_some) {
            return Err(format!(
                "--surface-nodes, --volume-nodes and --base-nodes apply to {selector}"
            ));
        }
        let d = ResonantNodes::DEFAULT;
        Ok(ResonantNodes {
            surface: self.surface_nodes.unwrap_or(d.surface),
            volume: self.volume_nodes.unwrap_or(d.volume),
            base: self.base_nodes.unwrap_or(d.base),
        })
    }
}

/// The integration rule that `eval`'s options select; names the option that does not fit.
fn integration_rule(
    integration: Option<IntegrationArg>,
    samples: Option<u32>,
    nodes: &NodeArgs,
) -> Result<Integration, String> {
    let integration = integration.unwrap_or(match samples {
        Some(_) => IntegrationArg::Paper,
        None => IntegrationArg::Direct,
    });
    let nodes = nodes.nodes(
        integration == IntegrationArg::Resonant,
        "--integration resonant",
    )?;
    match integration {
        IntegrationArg::Direct if samples.is_some() => {
            Err("--samples applies to paper mode, not --integration direct".into())
        }
        IntegrationArg::Direct => Ok(Integration::Direct),
        IntegrationArg::Paper => Ok(Integration::Paper(
            samples.unwrap_or(clothbake::model::curve::DEFAULT_PAPER_SAMPLES),
        )),
        IntegrationArg::Resonant if samples.is_some() => {
            Err("--samples applies to paper mode, not --integration resonant".into())
        }
        IntegrationArg::Resonant => Ok(Integration::Resonant(nodes)),
    }
}

/// A resonant node count, 1..=ResonantNodes::MAX.
fn resonant_count(text: &str) -> Result<u32, String> {
    let n: u32 = text.parse().map_err(|e| format!("{e}"))?;
    if (1..=ResonantNodes::MAX).contains(&n) {
        Ok(n)
    } else {
        Err(format!("must be in 1..={}", ResonantNodes::MAX))
    }
}

fn parse_layout(name: &str) -> Result<Layout, String> {
    Layout::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Layout::ALL.iter().map(|l| l.name()).collect();
        format!("unknown layout '{name}'; layouts: {}", names.join(", "))
    })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("clothbake: error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Fabrics { fabrics } => {
            let set = FabricSet::load_or_builtin(fabrics.as_deref()).map_err(|e| e.to_string())?;
            print!("{}", clothbake::fabric_file::describe(&set));
            Ok(())
        }
        Command::Eval {
            fabric,
            integration,
            samples,
            nodes,
            fabrics,
            table,
            pdf,
        } => {
            let integration = integration_rule(integration, samples, &nodes)?;
            let set = FabricSet::load_or_builtin(fabrics.as_deref()).map_err(|e| e.to_string())?;
            let fabric = set.require(&fabric)?;
            let patch = Patch::new(fabric, integration);
            let table = table
                .map(|path| read_table(&path).map_err(|e| e.to_string()))
                .transpose()?;
            let sampler = pdf.then(|| Sampler::for_fabric(fabric));
            let stdin = std::io::BufReader::new(std::io::stdin());
            let stdout = std::io::stdout().lock();
            eval_stream(stdin, stdout, |wi, wo| EvalOutput {
                f: patch.eval(wi, wo).to_array(),
                table: table
                    .as_ref()
                    .map(|t| clothbake::accuracy::lookup_f32(&t.table, wi, wo).to_array()),
                pdf: sampler.as_ref().map(|s| s.pdf(wo, wi)),
            })
            .map(|_| ())
            .map_err(|e| e.to_string())
        }
        Command::Sample {
            fabric,
            fabrics,
            table,
        } => {
            let set = FabricSet::load_or_builtin(fabrics.as_deref()).map_err(|e| e.to_string())?;
            let fabric = set.require(&fabric)?;
            let f = brdf_of(fabric, table.as_deref())?;
            let sampler = Sampler::for_fabric(fabric);
            let stdin = std::io::BufReader::new(std::io::stdin());
            let stdout = std::io::stdout().lock();
            sample_stream(stdin, stdout, |wo, u| match sampler.sample(wo, u) {
                Some(s) => SampleOutput {
                    wi: Some(s.wi.to_array()),
                    pdf: s.pdf,
                    weight: (f(s.wi, wo) / s.pdf).to_array(),
                },
                None => SampleOutput::REJECTED,
            })
            .map(|_| ())
            .map_err(|e| e.to_string())
        }
        Command::Albedo {
            fabric,
            fabrics,
            table,
            samples,
        } => {
            let set = FabricSet::load_or_builtin(fabrics.as_deref()).map_err(|e| e.to_string())?;
            let chosen: Vec<Fabric> = match &table {
                Some(path) => vec![read_table(path).map_err(|e| e.to_string())?.table.fabric],
                None if fabric.is_empty() => set.fabrics().to_vec(),
                None => fabric
                    .iter()
                    .map(|name| set.require(name).cloned())
                    .collect::<Result<_, _>>()?,
            };
            for fabric in &chosen {
                let f = brdf_of(fabric, table.as_deref())?;
                let rows = albedo_curve(&Sampler::for_fabric(fabric), f, samples as usize);
                print!("{}", describe_albedo(&fabric.name, &rows, samples as usize));
            }
            Ok(())
        }
        Command::Bake {
            fabric,
            scene,
            fabrics,
            layout,
            resolution,
            max_error,
            out,
            threads,
            force,
        } => {
            let scene = scene
                .map(|path| Scene::load(&path))
                .transpose()
                .map_err(|e| e.to_string())?;
            let fabric_file =
                fabrics.or_else(|| scene.as_ref().and_then(|s| s.fabric_file.clone()));
            let set =
                FabricSet::load_or_builtin(fabric_file.as_deref()).map_err(|e| e.to_string())?;
            let names = scene.as_ref().map_or(fabric, |s| s.fabrics.clone());
            let selected: Vec<Fabric> = if names.is_empty() {
                set.fabrics().to_vec()
            } else {
                names
                    .iter()
                    .map(|name| set.require(name).cloned())
                    .collect::<Result<_, _>>()?
            };
            let layout = layout.unwrap_or_else(|| {
                scene
                    .as_ref()
                    .map_or(Layout::THREAD_FRAME, |s| s.layout_or(Layout::THREAD_FRAME))
            });
            let budget = scene.as_ref().map(|s| s.budget).unwrap_or_default();
            let choice = match (
                resolution,
                max_error.or(budget.max_error),
                budget.max_bytes_per_fabric,
            ) {
                (Some(r), _, _) => ResolutionChoice::Fixed(r),
                (None, Some(e), _) if e.is_finite() && e > 0.0 => ResolutionChoice::MaxError(e),
                (None, Some(e), _) => {
                    return Err(format!("--max-error must be a positive number, got {e}"));
                }
                (None, None, Some(bytes)) => ResolutionChoice::MaxBytes(bytes),
                (None, None, None) => ResolutionChoice::Fixed(layout.default_resolution()),
            };
            let job = BakeJob {
                fabrics: selected,
                layout,
                resolution: choice,
                out,
                force,
            };
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.unwrap_or(0) as usize)
                .build()
                .map_err(|e| e.to_string())?;
            let progress = |name: &str, resolution: u32, rows: u64| -> Box<dyn Fn() + Sync> {
                let bar = progress_bar(rows, &format!("{name} @ {resolution}"));
                Box::new(move || bar.inc(1))
            };
            let mut report = |fabric: &Fabric, outcome: &Outcome| match outcome {
                Outcome::UpToDate { path, entry } => println!(
                    "{}: up to date ({} at resolution {}), not baked again",
                    path.display(),
                    entry.layout,
                    entry.resolution
                ),
                Outcome::Baked {
                    path,
                    entry,
                    bytes,
                    tried,
                } => {
                    for (r, e) in tried {
                        println!(
                            "{}: {layout} at resolution {r}: relative RMS {:.2}% uniform, {:.2}% highlight",
                            fabric.name,
                            100.0 * e.uniform.relative_rms,
                            100.0 * e.highlight.relative_rms
                        );
                    }
                    println!(
                        "{}: {} at resolution {}{}, {} KiB, baked in {:.1} s on {} threads",
                        path.display(),
                        entry.layout,
                        entry.resolution,
                        if tried.is_empty() {
                            ""
                        } else {
                            " (chosen for the error budget)"
                        },
                        bytes / 1024,
                        entry.bake_seconds,
                        entry.threads
                    );
                }
            };
            pool.install(|| bake_job::run(&job, &progress, &mut report))
                .map_err(|e| e.to_string())
        }
        #[cfg(feature = "runtime")]
        Command::Render {
            scene,
            fabric,
            out,
            width,
            height,
            frames,
            shader,
            samples,
            nodes,
            reference,
            reference_samples,
            linear,
            lookup,
        } => {
            let nodes = nodes.nodes(shader == RenderShaderArg::Resonant, "--shader resonant")?;
            let shader = match (shader, samples) {
                (RenderShaderArg::Direct, n) => render::job::Shader::Direct {
                    samples: n.unwrap_or(clothbake::gpu::direct::DEFAULT_SAMPLES),
                },
                (_, Some(_)) => return Err("--samples applies to --shader direct only".into()),
                (RenderShaderArg::Resonant, None) => render::job::Shader::Resonant { nodes },
                (RenderShaderArg::Lookup, None) => render::job::Shader::Lookup,
                (RenderShaderArg::Constant, None) => render::job::Shader::Constant,
            };
            let job = render::job::RenderJob {
                scene: scene.load()?,
                fabric,
                tables: scene.tables,
                out,
                width,
                height,
                frames,
                shader,
                horizon_band: lookup.horizon_band(),
                reference,
                reference_samples,
                linear,
                mesh: scene.mesh,
            };
            render::job::run(&job, &mut |line| println!("{line}")).map(|_| ())
        }
        #[cfg(feature = "runtime")]
        Command::View {
            scene,
            fabric,
            frames,
            samples,
            shader,
            lookup,
        } => view(clothbake::viewer::ViewOptions {
            scene: scene.load()?,
            fabric,
            tables: scene.tables,
            mesh: scene.mesh,
            frames,
            samples,
            shading: match shader {
                ShaderArg::Lookup => clothbake::viewer::Shading::Lookup,
                ShaderArg::Direct => clothbake::viewer::Shading::Direct,
                ShaderArg::Resonant => clothbake::viewer::Shading::Resonant,
            },
            horizon_band: lookup.horizon_band(),
        }),
        #[cfg(feature = "runtime")]
        Command::Report { quick, out } => {
            let fabrics = FabricSet::builtin().fabrics().to_vec();
            let config = if quick {
                clothbake::report::ReportConfig::quick(fabrics)
            } else {
                clothbake::report::ReportConfig::full(fabrics)
            };
            let command_line = std::env::args().collect();
            let report = clothbake::report::run(&config, &out, command_line, &mut |line| {
                eprintln!("report: {line}")
            })
            .map_err(|e| e.to_string())?;
            println!(
                "{}: {} in {:.0} s",
                out.display(),
                report.files.join(", "),
                report.elapsed_seconds
            );
            Ok(())
        }
        Command::Wgsl {
            table,
            lang,
            no_horizon_band,
        } => {
            let file = read_table(&table).map_err(|e| e.to_string())?;
            let options = LookupShaderOptions {
                horizon_band: !no_horizon_band,
            };
            print!("{}", lookup_shader(&file.table, lang, &options)?);
            Ok(())
        }
        Command::Check { table, pairs } => {
            let file = read_table(&table).map_err(|e| e.to_string())?;
            let error = measure(&file.table, &file.table.fabric, pairs as usize);
            let t = &file.table;
            let baked = manifest::entry_for(&table, &file.hash).map_or_else(
                || "bake time not recorded (no matching manifest entry)".to_string(),
                |e| format!("baked in {:.1} s on {} threads", e.bake_seconds, e.threads),
            );
            println!(
                "{}: fabric {}, {} at resolution {}, {} KiB of f16 texels, clothbake {} \
                 (baker revision {}), {baked}",
                table.display(),
                file.table.fabric.name,
                t.layout,
                t.resolution,
                t.byte_size() / 1024,
                file.version,
                file.baker_revision
            );
            for (label, e) in [
                ("uniform pairs", error.uniform),
                ("  both ≥ 1° elevation", error.uniform_above_1deg),
                ("  both ≥ 3° elevation", error.uniform_above_3deg),
                ("  both ≥ 15° elevation", error.uniform_above_15deg),
                ("highlight pairs", error.highlight),
                ("  both ≥ 1° elevation", error.highlight_above_1deg),
                ("  both ≥ 3° elevation", error.highlight_above_3deg),
            ] {
                println!(
                    "  {label:<31} relative RMS {:>7.3}%   max |error| {:.3e} (where F = {:.3e})",
                    100.0 * e.relative_rms,
                    e.max_abs,
                    e.max_abs_at_value
                );
            }
            Ok(())
        }
    }
}

/// F(wi, wo) by the direct evaluation of `fabric`, or by the f32 lookup of the table at
/// `table` when given.
fn brdf_of(
    fabric: &Fabric,
    table: Option<&std::path::Path>,
) -> Result<Box<dyn Fn(glam::DVec3, glam::DVec3) -> glam::DVec3 + Sync>, String> {
    Ok(match table {
        Some(path) => {
            let table = read_table(path).map_err(|e| e.to_string())?.table;
            Box::new(move |wi, wo| clothbake::accuracy::lookup_f32(&table, wi, wo))
        }
        None => {
            let patch = Patch::new(fabric, Integration::Direct);
            Box::new(move |wi, wo| patch.eval(wi, wo))
        }
    })
}

/// `clothbake view`: runs the viewer, then reports the frames drawn and their median time.
#[cfg(feature = "runtime")]
fn view(options: clothbake::viewer::ViewOptions) -> Result<(), String> {
    let summary = clothbake::viewer::run(options).map_err(|e| e.to_string())?;
    let ms = |v: Option<f64>| v.map_or_else(|| "n/a".to_string(), |v| format!("{v:.2} ms"));
    println!(
        "clothbake view: drew {} frames on {}; median frame time {} (CPU interval), GPU {}",
        summary.frames,
        summary.adapter,
        ms(summary.median_frame_ms),
        ms(summary.median_gpu_ms)
    );
    Ok(())
}

/// A progress bar on an interactive terminal, hidden otherwise.
fn progress_bar(length: u64, label: &str) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(length);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{msg:32} [{bar:40}] {percent:>3}% {eta}")
    {
        bar.set_style(style);
    }
    bar.set_message(label.to_string());
    bar
}
