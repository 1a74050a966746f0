//! `lightbench reference --device gpu` as a user runs it: the CPU reference's files and
//! manifest fields (the device aside), its cache, and a clear refusal without ray queries.

use crate::cli_common::{lightbench, scratch};

fn manifest(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("reference.json")).unwrap()).unwrap()
}

#[test]
fn the_gpu_reference_writes_what_the_cpu_one_writes() {
    let dir = scratch("gpu-reference");
    let run = |device: &str| {
        let out = dir.join(device);
        let args = [
            "reference",
            "--device",
            device,
            "--scene",
            "cornell_lamp",
            "--size",
            "16x12",
            "--terms",
            "direct,full,ao",
            "--spp",
            "8",
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ];
        let (code, _, err) = lightbench(&args);
        assert_eq!(code, 0, "{err}");
        (out, err)
    };
    let (cpu, _) = run("cpu");
    let (gpu, first) = run("gpu");
    assert!(first.contains("reference rendered"), "{first}");
    let (m_cpu, m_gpu) = (manifest(&cpu), manifest(&gpu));
    let keys = |m: &serde_json::Value| m.as_object().unwrap().keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys(&m_cpu), keys(&m_gpu));
    for field in [
        "version",
        "scene",
        "size",
        "settings",
        "spp",
        "triangles",
        "terms",
        "term_samples",
        "emitters",
    ] {
        assert_eq!(m_cpu[field], m_gpu[field], "{field}");
    }
    assert_eq!(m_cpu["device"], "cpu");
    assert!(
        m_gpu["device"]["gpu"].as_str().is_some_and(|n| !n.is_empty()),
        "{}",
        m_gpu["device"]
    );
    assert_ne!(m_cpu["key"], m_gpu["key"], "the device is part of the cache key");
    for term in ["direct", "full", "ao"] {
        for file in [format!("{term}.exr"), format!("{term}.variance.exr"), format!("{term}.png")] {
            assert!(gpu.join(&file).is_file(), "{file}");
        }
    }
    let (_, again) = run("gpu");
    assert!(again.contains("up to date"), "{again}");
}

#[test]
fn a_gpu_without_ray_queries_is_refused_by_name() {
    let out = scratch("gpu-reference-gl");
    let (code, _, err) = lightbench(&[
        "reference",
        "--device",
        "gpu",
        "--backend",
        "gl",
        "--scene",
        "cornell",
        "--size",
        "8x8",
        "--terms",
        "full",
        "--spp",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("no ray queries") && err.contains("EXPERIMENTAL_RAY_QUERY"), "{err}");
    let (code, _, err) = lightbench(&[
        "reference",
        "--device",
        "gpu",
        "--terms",
        "indirect_diffuse",
        "--size",
        "8x8",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("`indirect_diffuse` is the CPU reference's only"), "{err}");
    // Nothing to trace: said, not a build error of the acceleration structure.
    let empty = out.join("empty.ron");
    std::fs::write(
        &empty,
        "Scene(name: \"empty\", size: (8, 8), camera: (position: (0.0, 1.0, 3.0)), lights: [Point(position: (0.0, 2.0, 0.0), intensity: 1.0, range: 5.0)])\n",
    )
    .unwrap();
    let (code, _, err) = lightbench(&[
        "reference",
        "--device",
        "gpu",
        "--scene",
        empty.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.starts_with("error: scene `empty` has no triangles for the GPU path tracer"),
        "{err}"
    );
}

/// A sweep takes its reference from the GPU path tracer with `device: gpu`, and says where a
/// term the GPU path tracer lacks is asked of it.
#[test]
fn a_sweep_measures_against_the_gpu_reference() {
    let dir = scratch("gpu-reference-sweep");
    let pipeline = crate::cli_common::root().join("pipelines/deferred.lbp");
    let spec = |reference: &str| {
        format!(
            "Sweep(\n    pipeline: {:?},\n    scenes: [\"cornell\"],\n    sizes: [(16, 16)],\n    set: {{\"ambient.color\": \"(0, 0, 0)\"}},\n    points: [{{\"shadows\": \"rt\"}}],\n    effect: [\"light_rt\"],\n    compare: \"hdr\",\n    reference: {reference},\n    warmup: 1,\n    frames: 2,\n)\n",
            pipeline.display().to_string()
        )
    };
    let good = dir.join("good.ron");
    std::fs::write(&good, spec("(term: direct, spp: 2, device: gpu)")).unwrap();
    let out = dir.join("out");
    let (code, _, err) = lightbench(&["sweep", good.to_str().unwrap(), "--out", out.to_str().unwrap(), "--quiet"]);
    assert_eq!(code, 0, "{err}");
    let refs: Vec<_> = std::fs::read_dir(out.join("references"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(refs.len(), 1);
    assert!(manifest(&refs[0])["device"]["gpu"].is_string());
    // The regional measure is among the results: ray-traced shadows against the GPU's `direct`.
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let (head, row) = csv.split_once('\n').unwrap();
    let at = head.split(',').position(|h| h == "block_p10").expect("a block_p10 column");
    let p10: f64 = row.split(',').nth(at).unwrap().parse().unwrap();
    assert!(
        (0.9..1.1).contains(&p10),
        "shadow rays are the reference's direct light, block by block: {p10}"
    );
    let bad = dir.join("bad.ron");
    std::fs::write(&bad, spec("(term: indirect_diffuse, device: gpu)")).unwrap();
    let (code, _, err) = lightbench(&[
        "sweep",
        bad.to_str().unwrap(),
        "--out",
        dir.join("out2").to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("bad.ron:9:41:") && err.contains("no term `indirect_diffuse`"), "{err}");
}

/// `--target-error` on the GPU: a pilot, then the samples predicted, until the percentile of
/// the lit pixels' relative standard error reaches the target, reported as on the CPU.
#[test]
fn the_gpu_reference_renders_to_an_error_target() {
    let out = scratch("gpu-reference-target");
    let (code, _, err) = lightbench(&[
        "reference",
        "--device",
        "gpu",
        "--scene",
        "cornell",
        "--size",
        "16x16",
        "--terms",
        "full",
        "--target-error",
        "0.1",
        "--percentile",
        "90",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("at the 90th percentile of lit pixels") && err.contains("(target 0.1: reached)"),
        "{err}"
    );
    let m = manifest(&out);
    let reached = &m["reached"];
    assert!(reached["error"].as_f64().unwrap() <= 0.1, "{reached}");
    assert!(m["spp"].as_u64().unwrap() > 64, "more than the pilot: {}", m["spp"]);
}

/// Bad inputs of the GPU reference: each said, with its exit code, and nothing written.
#[test]
fn bad_gpu_reference_inputs_are_refused_and_write_nothing() {
    let dir = scratch("gpu-reference-bad");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    for (args, code, says) in [
        (
            vec!["--device", "gpu", "--pipeline", "no/such.lbp"],
            2,
            "no such pipeline file: no/such.lbp",
        ),
        (
            vec!["--device", "gpu", "--adapter", "no such adapter"],
            1,
            "no adapter matches `no such adapter`",
        ),
        (
            vec!["--pipeline", "pipelines/pathtrace.lbp"],
            2,
            "--pipeline chooses how the GPU reference renders: it needs --device gpu",
        ),
        (vec!["--adapter", "llvmpipe"], 2, "--adapter chooses how the GPU reference renders"),
        (
            vec!["--device", "gpu", "--integrator", "scalar"],
            2,
            "--integrator chooses how the CPU reference renders",
        ),
        (vec!["--integrator", "vector"], 2, "invalid value 'vector' for '--integrator"),
        (vec!["--device", "tpu"], 2, "invalid value 'tpu'"),
    ] {
        let mut all = vec!["reference", "--scene", "cornell", "--size", "8x8", "--spp", "1", "--out", o];
        all.extend(args);
        let (got, _, err) = lightbench(&all);
        assert_eq!(got, code, "{all:?}: {err}");
        assert!(err.contains(says), "{all:?}: {err}");
        assert!(!out.exists(), "{all:?} wrote {}", out.display());
    }
    // A sweep's reference device that is not one, located in the spec.
    let spec = dir.join("tpu.ron");
    let pipeline = crate::cli_common::root().join("pipelines/deferred.lbp");
    std::fs::write(
        &spec,
        format!("Sweep(\n    pipeline: {:?},\n    scenes: [\"cornell\"],\n    points: [{{}}],\n    effect: [\"gbuffer\"],\n    compare: \"hdr\",\n    reference: (term: direct, device: tpu),\n)\n", pipeline.display().to_string()),
    )
    .unwrap();
    let (got, _, err) = lightbench(&["sweep", spec.to_str().unwrap(), "--out", o, "--quiet"]);
    assert_eq!(got, 1, "{err}");
    assert!(
        err.contains("tpu.ron:7:") && err.contains("`tpu`") && err.contains("expected either `cpu` or `gpu`"),
        "{err}"
    );
    assert!(!out.exists());
}

/// docs/reference.md's GPU example, run as written (in a project that `lightbench init` made,
/// where `pipelines/pathtrace.lbp` is the path a user types).
#[test]
fn the_documented_gpu_example_runs_as_written() {
    let doc = std::fs::read_to_string(crate::cli_common::root().join("docs/reference.md")).unwrap();
    let block = doc
        .split("```sh\n")
        .map(|b| b.split("```").next().unwrap())
        .find(|b| b.contains("--device gpu"))
        .expect("the GPU example");
    let dir = scratch("gpu-reference-doc");
    let (code, _, err) = crate::cli_common::lightbench_in(&dir, &["init", "."]);
    assert_eq!(code, 0, "{err}");
    for line in block.lines() {
        let args: Vec<&str> = line.split_whitespace().skip(1).collect();
        let (code, _, err) = crate::cli_common::lightbench_in(&dir, &args);
        assert_eq!(code, 0, "{line}: {err}");
    }
    assert!(dir.join("ref-gpu/full.exr").is_file() && dir.join("ref-gpu/direct.variance.exr").is_file());
    let img = image::open(dir.join("traced.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (64, 64));
    assert!(img.pixels().any(|p| p != img.get_pixel(0, 0)), "a lit, non-uniform image");
}
