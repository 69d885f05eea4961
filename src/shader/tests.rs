use super::*;
use crate::table::Layout;
use crate::table::wgsl::{layout_module, lookup_composer, lookup_wgsl_in_group};

/// The generated modules that registered files may require.
const GENERATED: [&str; 5] = [
    BRDF,
    TABLE_CONSTANTS,
    RESONANT_RULES,
    RESONANT_FABRIC,
    SAMPLER_CONSTANTS,
];

fn order(composer: &Composer, roots: &[&str]) -> Result<Vec<String>, ComposeError> {
    composer.order(roots)
}

#[test]
fn requirements_come_from_the_header_only() {
    let source = "// A module.\n// requires: a, b\n//   requires: c d\n//\n// requires: e,\n\n\
                  // requires: not_header\nfn f() {}\n";
    assert_eq!(requirements(source), ["a", "b", "c", "d", "e"]);
    assert!(requirements("fn f() {}\n// requires: x\n").is_empty());
    assert!(requirements("").is_empty());
}

#[test]
fn modules_come_after_what_they_require() {
    let composer = Composer::new()
        .module("top", "// requires: middle, leaf\nfn top() {}\n")
        .module("middle", "// requires: leaf\nfn middle() {}\n")
        .module("leaf", "fn leaf() {}\n");
    assert_eq!(
        order(&composer, &["top"]).unwrap(),
        ["leaf", "middle", "top"]
    );
    // Roots in order, each after what it requires.
    assert_eq!(
        order(&composer, &["leaf", "top"]).unwrap(),
        ["leaf", "middle", "top"]
    );
    let text = composer.compose(&["top"]).unwrap();
    let at = |f: &str| text.find(f).unwrap_or_else(|| panic!("{f} in {text}"));
    assert!(at("fn leaf") < at("fn middle") && at("fn middle") < at("fn top"));
}

#[test]
fn a_module_required_twice_is_written_once() {
    let composer = Composer::new()
        .module("top", "// requires: left, right\nfn top() {}\n")
        .module("left", "// requires: base\nfn left() {}\n")
        .module("right", "// requires: base\nfn right() {}\n")
        .module("base", "fn base() {}\n");
    assert_eq!(
        order(&composer, &["top", "base", "left"]).unwrap(),
        ["base", "left", "right", "top"]
    );
    let text = composer.compose(&["top", "right"]).unwrap();
    assert_eq!(text.matches("fn base()").count(), 1, "{text}");
    // Files too: a registered file requires a generated module, and two modules require the
    // same file.
    let sampled = "// requires: model/tangent_sample\nfn sampled() {}\n";
    let sampled_too = "// requires: model/tangent_sample\nfn sampled_too() {}\n";
    let both = Composer::new()
        .module("sampled", sampled)
        .module("sampled_too", sampled_too);
    let files = order(&both, &["table/lookup", "sampled", "sampled_too"]);
    let Err(ComposeError::Unknown { name, .. }) = files else {
        panic!("the lookup requires the generated table constants: {files:?}");
    };
    assert_eq!(name, TABLE_CONSTANTS);
    let composer = both.module(TABLE_CONSTANTS, "");
    let files = order(&composer, &["table/lookup", "sampled", "sampled_too"]).unwrap();
    let count = |n: &str| files.iter().filter(|f| *f == n).count();
    assert_eq!(count("model/tangent_sample"), 1, "{files:?}");
    assert_eq!(files.last().map(String::as_str), Some("sampled_too"));
}

#[test]
fn a_cycle_is_an_error() {
    let composer = Composer::new()
        .module("a", "// requires: b\n")
        .module("b", "// requires: c\n")
        .module("c", "// requires: a\n");
    let error = composer.compose(&["a"]).unwrap_err();
    assert_eq!(
        error,
        ComposeError::Cycle {
            path: ["a", "b", "c", "a"].map(String::from).to_vec()
        }
    );
    assert!(error.to_string().contains("a -> b -> c -> a"), "{error}");
    let itself = Composer::new().module("a", "// requires: a\n");
    assert!(matches!(
        itself.compose(&["a"]),
        Err(ComposeError::Cycle { .. })
    ));
}

#[test]
fn an_unknown_name_is_an_error() {
    let composer = Composer::new().module("a", "// requires: model/tangent_sample, nowhere\n");
    assert_eq!(
        composer.compose(&["a"]).unwrap_err(),
        ComposeError::Unknown {
            name: "nowhere".into(),
            required_by: Some("a".into())
        }
    );
    assert_eq!(
        Composer::new().compose(&["table/nowhere"]).unwrap_err(),
        ComposeError::Unknown {
            name: "table/nowhere".into(),
            required_by: None
        }
    );
}

#[test]
fn a_name_cannot_be_defined_twice() {
    let twice = Composer::new().module("a", "").module("a", "");
    assert_eq!(
        twice.compose(&["a"]).unwrap_err(),
        ComposeError::Duplicate { name: "a".into() }
    );
    let file = Composer::new().module("table/lookup", "");
    assert!(matches!(
        file.compose(&["table/lookup"]),
        Err(ComposeError::Duplicate { .. })
    ));
}

#[test]
fn the_brdf_group_is_bound_in_every_module() {
    let composer = Composer::new()
        .module(
            "a",
            "// requires: b\n@group(CLOTH_BRDF_GROUP) @binding(1) var<uniform> x: f32;\n",
        )
        .module(
            "b",
            "@group(CLOTH_BRDF_GROUP) @binding(2) var<uniform> y: f32;\n\
             @group(1) @binding(0) var<uniform> z: f32;\n",
        );
    let text = composer.compose(&["a"]).unwrap();
    assert_eq!(text.matches("@group(0) @binding(").count(), 2, "{text}");
    assert!(text.contains("@group(1) @binding(0)"));
    let text = composer
        .brdf_group("#{MATERIAL_BIND_GROUP}")
        .compose(&["a"])
        .unwrap();
    assert_eq!(
        text.matches("@group(#{MATERIAL_BIND_GROUP}) @binding(")
            .count(),
        2
    );
    assert!(!text.contains(BRDF_GROUP_PLACEHOLDER));
}

#[test]
fn every_file_is_registered_once_and_requires_known_modules() {
    for (i, f) in FILES.iter().enumerate() {
        assert!(
            FILES[..i].iter().all(|g| g.name != f.name),
            "{} twice",
            f.name
        );
        for required in requirements(f.source) {
            assert!(
                file(required).is_some() || GENERATED.contains(&required),
                "{} requires unknown '{required}'",
                f.name
            );
        }
    }
    // Every file of shaders/ is registered.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = root.join("shaders");
    let mut on_disk = Vec::new();
    let mut stack = vec![dir.clone()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("shaders/") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                let rel = path.strip_prefix(&dir).expect("under shaders/");
                on_disk.push(rel.with_extension("").to_string_lossy().replace('\\', "/"));
            }
        }
    }
    on_disk.sort();
    // The layouts' own files are their units', under the same names.
    let layouts = Layout::ALL.iter().map(|l| l.unit().wgsl_file());
    for unit_file in layouts.clone() {
        let on_disk = std::fs::read_to_string(root.join(unit_file.path)).expect(unit_file.path);
        assert_eq!(on_disk, unit_file.source, "{}", unit_file.path);
        assert_eq!(format!("shaders/{}.wgsl", unit_file.name), unit_file.path);
    }
    let mut registered: Vec<&str> = FILES
        .iter()
        .map(|f| f.name)
        .chain(layouts.map(|f| f.name))
        .collect();
    registered.sort();
    assert_eq!(on_disk, registered);
    for &layout in Layout::ALL {
        assert!(
            file(layout_module(layout)).is_none(),
            "{layout}: registered twice"
        );
    }
}

#[test]
fn every_unit_file_under_src_is_a_shader_file_constant_beside_it() {
    // A unit's own WGSL (an evaluator's, in its folder) reaches the composer only as a
    // `ShaderFile` constant of a Rust file in the same folder, which includes it and names
    // its path; a file no constant includes would never be composed or validated.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut stack = vec![root.join("src")];
    let mut found = 0;
    while let Some(dir) = stack.pop() {
        let entries: Vec<_> = std::fs::read_dir(&dir)
            .expect("src/")
            .map(|e| e.expect("entry").path())
            .collect();
        let rust: String = entries
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "rs"))
            .map(|p| std::fs::read_to_string(p).expect("a Rust file"))
            .collect();
        for path in entries {
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                let name = path.file_name().unwrap().to_string_lossy().to_string();
                let relative = path
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                assert!(
                    rust.contains(&format!("include_str!(\"{name}\")"))
                        && rust.contains(&format!("path: \"{relative}\"")),
                    "{relative}: no ShaderFile constant beside it includes it and names its path"
                );
                found += 1;
            }
        }
    }
    assert!(found > 0, "no unit files under src/");
}

/// Parses and validates `source` with naga, as wgpu does before a pipeline.
fn validate(what: &str, source: &str) -> naga::Module {
    assert!(
        !source.contains(BRDF_GROUP_PLACEHOLDER),
        "{what}: unbound group"
    );
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{what}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{what}: {e:?}"));
    module
}

fn defines(module: &naga::Module, function: &str) -> bool {
    module
        .functions
        .iter()
        .any(|(_, f)| f.name.as_deref() == Some(function))
        || module.entry_points.iter().any(|e| e.name == function)
}

/// Every composition the crate makes, validated by naga: each layout's lookup for every
/// built-in fabric (alone, in another group, with the pair
/// kernel of `wgsl --lang`), and with the runtime each GPU evaluator's shader, the pair
/// kernel over each, the renderer over each (and over its G-buffer stub) and the sampler's
/// kernels.
#[test]
fn every_composition_validates() {
    let fabrics = crate::formats::fabric_toml::FabricSet::builtin();
    let mut brdfs: Vec<(String, String)> = Vec::new();
    for fabric in fabrics.fabrics() {
        for &layout in Layout::ALL {
            // The generated WGSL depends on the geometry only: zero texels at the smallest resolution.
            let table = crate::table::zero_table(fabric, layout, layout.resolution_ladder()[0]);
            let what = format!("{} {layout}", fabric.name);
            let composer = lookup_composer(&table);
            let lookup = composer.compose(&[BRDF]).expect("lookup");
            let module = validate(&what, &lookup);
            assert!(defines(&module, "cloth_brdf"), "{what}");
            assert!(defines(&module, &format!("cloth_{layout}_brdf")), "{what}");
            let kernel = composer
                .compose(&[crate::table::shader_language::KERNEL_MODULE])
                .expect("kernel");
            assert!(defines(&validate(&what, &kernel), "eval_pairs_main"));
            validate(&what, &lookup_wgsl_in_group(&table, "2"));
            brdfs.push((what, lookup));
        }
        // Every registered evaluator's GPU form at its default spelling (the table's, read
        // from a file, is the layouts' above).
        #[cfg(feature = "runtime")]
        for unit in crate::evaluator::EVALUATORS {
            use crate::evaluator::EvaluatorError;
            let evaluator = (unit.parse)(None).unwrap();
            let context = crate::evaluator::EvaluationContext {
                tables: std::path::PathBuf::from("no tables here"),
            };
            let wgsl = match evaluator.prepare(fabric, &context) {
                Ok(evaluation) => evaluation.gpu_wgsl(),
                Err(EvaluatorError::Table(_)) => continue,
                Err(e) => panic!("{}: {e}", unit.name),
            };
            match wgsl {
                Ok(wgsl) => brdfs.push((format!("{} {}", fabric.name, evaluator.spelling()), wgsl)),
                Err(EvaluatorError::NoGpuForm { .. }) => {}
                Err(e) => panic!("{}: {e}", unit.name),
            }
        }
    }
    #[cfg(feature = "runtime")]
    {
        for (what, brdf) in &brdfs {
            assert!(defines(&validate(what, brdf), "cloth_brdf"), "{what}");
            let pairs = crate::gpu::eval_pairs_wgsl(brdf.clone());
            assert!(defines(&validate(what, &pairs), "eval_pairs_main"));
            let render = crate::render::render_wgsl(brdf);
            assert!(defines(&validate(what, &render), "fs_display"));
        }
        let stub = crate::render::render_wgsl(crate::render::STUB_BRDF_WGSL);
        assert!(defines(&validate("render stub", &stub), "fs_gbuffer"));
        let sampler = crate::gpu::sampler::sampler_pairs_wgsl();
        let module = validate("sampler", &sampler);
        assert!(defines(&module, "sample_draws_main") && defines(&module, "sample_pdf_main"));
    }
    assert!(!brdfs.is_empty());
}
