//! The ray-traced options (shadows, AO, indirect diffuse, reflections, area lights) against
//! the reference: their rays trace the same triangles the path tracer does and shade hits with
//! its definitions, so each converges to the reference's term, region by region. (Kept apart
//! from the reference's own tests, one of which times the reference: these load every core.)

use super::gpu_common;
use lightbench::io::Image;

/// `shadows = rt` with ambient 0 equals the reference's `direct` term: on the Cornell box, the
/// sun- and spot-lit boxes and every hard scene, ≥ 99% of values within 2% and lit where the
/// reference is lit (give or take edge pixels) — where shadow maps need per-scene exceptions.
/// `many_lights` is the one exception, as for shadow maps: its 100 lights are `shadows: false`,
/// which the raster honours and the reference (the truth it approximates) does not.
#[test]
fn ray_traced_shadows_equal_the_reference_direct_light() {
    let mut files: Vec<_> = std::fs::read_dir(gpu_common::root().join("scenes/hard"))
        .unwrap()
        .map(|e| e.unwrap().path().to_string_lossy().into_owned())
        .filter(|p| p.ends_with(".ron"))
        .collect();
    files.sort();
    assert!(files.len() >= 20, "{files:?}");
    let mut scenes = vec!["cornell".to_string()];
    for f in ["scenes/cornell_sun.ron", "scenes/cornell_spot.ron"] {
        scenes.push(gpu_common::root().join(f).to_string_lossy().into_owned());
    }
    scenes.extend(files);
    let mut failures = vec![];
    for name in &scenes {
        let s = lightbench::scene::load::load_sized(name, Some((64, 64)), &[]).unwrap();
        let (raster, reference) =
            gpu_common::raster_and_direct(&s, &gpu_common::deferred(), &[("shadows", "rt")], &[("ambient.color", "(0, 0, 0)")]);
        assert!(raster.rgba.iter().all(|v| v.is_finite()), "{}: NaN or Inf", s.name);
        let (share, median) = gpu_common::agreement(&raster, &reference, 0.02);
        let lit = |img: &Image| img.rgba.chunks_exact(4).filter(|p| p[0] + p[1] + p[2] > 0.01).count();
        let (a, b) = (lit(&reference), lit(&raster));
        let min_share = if s.name == "many_lights" { 0.7 } else { 0.99 };
        if share < min_share || median >= 0.005 || a.abs_diff(b) > b / 50 + 4 {
            failures.push(format!(
                "{}: {:.2}% within 2%, median {median:.4}, {a} vs {b} lit pixels",
                s.name,
                share * 100.0
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The Cornell box (its light under the ceiling) with its tall box blended (alpha 0.4, both
/// sides) and its short box alpha-masked by a checker of holes: shadows through cut-outs.
fn box_with_cut_outs() -> lightbench::scene::Scene {
    use lightbench::scene::{AlphaMode, ImageData, Material};
    let mut s = lightbench::scene::load::load_sized("cornell", Some((64, 64)), &[]).unwrap();
    s.name = "cut_outs".into();
    let n = 4u32;
    s.textures.push(ImageData {
        width: n,
        height: n,
        rgba: (0..n * n)
            .flat_map(|i| [200, 200, 200, if (i % n + i / n).is_multiple_of(2) { 255 } else { 0 }])
            .collect(),
        srgb: true,
    });
    let mut tall = Material::color("tall", [0.7, 0.6, 0.5], 0.8);
    (tall.base_color[3], tall.alpha, tall.double_sided) = (0.4, AlphaMode::Blend, true);
    let mut short = Material::color("short", [1.0; 3], 0.8);
    (short.base_color_texture, short.alpha) = (Some(s.textures.len() - 1), AlphaMode::Mask(0.5));
    for (m, mesh) in [(tall, "tall_box"), (short, "short_box")] {
        s.materials.push(m);
        let i = s.materials.len() - 1;
        s.meshes.iter_mut().find(|x| x.name == mesh).unwrap().material = i;
    }
    s
}

/// Ray-traced shadows let light through cut-outs as the reference does: a blended surface
/// passes 1 − alpha of it (the mean of the reference's coins), a masked one passes it through
/// its holes. On the floor and walls (the pixels that see neither box, edges left out),
/// `shadows = rt` with ambient 0 is within 4σ of the reference's `direct` (256 spp, its
/// noise from the coins) plus 1% for ≥ 99% of values — tracing the boxes whole (or skipping
/// the blended one) leaves their shadows 0 or unshadowed, far outside.
#[test]
fn ray_traced_shadows_pass_through_cut_outs_as_the_reference() {
    use lightbench::reference::{Budget, Settings, Term};
    let s = box_with_cut_outs();
    let settings = Settings {
        budget: Budget::Spp(256),
        terms: vec![Term::Direct],
        ..Settings::default()
    };
    let r = lightbench::reference::render(&s, &settings, false);
    let reference = r.term(Term::Direct).unwrap();
    let g = gpu_common::gpu();
    let v = [("shadows", "rt")].map(|(a, b)| (a.to_string(), b.to_string()));
    let (exe, _) = lightbench::render::compile(&g, &gpu_common::deferred(), None, &s, &v).unwrap_or_else(|e| panic!("{e}"));
    let set = [("ambient.color".to_string(), "(0, 0, 0)".to_string())];
    let params = lightbench::render::parse_params(&exe.plan, &set).unwrap();
    let ex = lightbench::render::render_with(&g, &exe, &s, 1, &params).unwrap();
    let hdr = ex.read_texture(&g, "hdr", 0, 0).unwrap();
    let judged = beside_the_boxes(&s);
    let (mut n, mut out, mut shaded) = (0usize, 0usize, 0usize);
    for i in (0..judged.len()).filter(|&i| judged[i]) {
        for c in 0..3 {
            let (a, b) = (hdr.rgba[i * 4 + c] as f64, reference.mean.rgba[i * 4 + c] as f64);
            assert!(a.is_finite(), "pixel {i}: {a}");
            let sigma = (reference.variance.rgba[i * 4 + c] as f64).sqrt();
            n += 1;
            out += ((a - b).abs() > 4.0 * sigma + 0.01 * b.abs() + 1e-3) as usize;
            // Partly shadowed: where the coins left noise (neither all lit nor all dark).
            shaded += (c == 0 && sigma > 0.01 * b.abs()) as usize;
        }
    }
    eprintln!("cut-out shadows: {out} of {n} values outside, {shaded} pixels partly shadowed");
    assert!(shaded >= 40, "the blended box's shadow falls on the judged pixels: {shaded}");
    assert!(n > 6000 && out * 100 <= n, "{out} of {n} values outside the reference's noise");
}

/// The Cornell box calling for ambient occlusion, `n`×`n` pixels (a scene file, as a user
/// writes one).
fn cornell_ao(n: u32) -> lightbench::scene::Scene {
    let d = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("lightbench-rtao-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let file = d.join(format!("ao{n}.ron"));
    let text = format!("Scene(name: \"ao\", size: ({n}, {n}), builtin: \"cornell\", effects: [AmbientOcclusion])\n");
    std::fs::write(&file, text).unwrap();
    lightbench::scene::load(file.to_str().unwrap()).unwrap()
}

/// `ao = rtao` at a high ray count converges to the reference's `ao` term: on the Cornell box
/// (64², radius 0.5 world units, with and without `ao.falloff`), and on the box with cut-outs
/// (rays through the masked box's holes, through the blended one by coins), 256 rays per
/// pixel unblurred (`ao.raw`, full size) against 512 reference samples: the mean bias is
/// within 0.01 and each pixel's difference is within its noise (|z| < 4.5 for ≥ 99% of
/// pixels, the z-score's variance near 1).
#[test]
fn ray_traced_ao_converges_to_the_reference_ao() {
    let everywhere = vec![true; 64 * 64];
    for falloff in [false, true] {
        rtao_against_the_reference(&cornell_ao(64), falloff, &everywhere);
    }
    let mut cut = box_with_cut_outs();
    cut.effects.insert(lightbench_compiler::ir::Effect::AmbientOcclusion);
    rtao_against_the_reference(&cut, false, &beside_the_boxes(&cut));
}

/// The pixels whose camera ray meets neither box (nor an edge): where the raster G-buffer and
/// the reference see the same surface when the boxes are cut out or blended.
fn beside_the_boxes(s: &lightbench::scene::Scene) -> Vec<bool> {
    let boxes: Vec<usize> = ["tall_box", "short_box"]
        .iter()
        .map(|b| s.meshes.iter().position(|m| &m.name == b).unwrap())
        .collect();
    let edges = lightbench::reference::edge_pixels(s);
    let seen = lightbench::reference::surfaces_seen(s);
    seen.iter()
        .zip(edges)
        .map(|(label, edge)| label.is_some_and(|l| !boxes.contains(&l)) && !edge)
        .collect()
}

/// `ao = rtao` (256 rays, unblurred) against the reference's `ao` (512 samples) over the
/// `judged` pixels of `scene`.
fn rtao_against_the_reference(scene: &lightbench::scene::Scene, falloff: bool, judged: &[bool]) {
    use lightbench::reference::{Budget, Settings, Term};
    let settings = Settings {
        budget: Budget::Spp(512),
        terms: vec![Term::Ao],
        ao_radius: 0.5,
        ao_falloff: falloff,
        ..Settings::default()
    };
    let r = lightbench::reference::render(scene, &settings, false);
    let reference = r.term(Term::Ao).unwrap();
    let g = gpu_common::gpu();
    let pipeline = gpu_common::root().join("pipelines/deferred_gi.lbp");
    let fall = if falloff { "inverse_square" } else { "range" };
    let v = [("ao", "rtao"), ("indirect_diffuse", "off"), ("ao_falloff", fall)].map(|(a, b)| (a.to_string(), b.to_string()));
    let (exe, _) = lightbench::render::compile(&g, &pipeline, None, scene, &v).unwrap_or_else(|e| panic!("{e}"));
    assert!(exe.plan.passes.iter().any(|p| p.name == "rtao"), "rtao runs");
    let set = [
        ("ao.radius", "0.5"),
        ("lengths.world", "true"),
        ("ao.rt.rays", "256"),
        ("ao.scale", "1"),
    ]
    .map(|(a, b)| (a.to_string(), b.to_string()));
    let params = lightbench::render::parse_params(&exe.plan, &set).unwrap();
    let ex = lightbench::render::render_with(&g, &exe, scene, 1, &params).unwrap();
    let raw = ex.read_texture(&g, "ao.raw", 0, 0).unwrap();
    let (mut diff, mut n, mut z_out, mut z2) = (0.0f64, 0usize, 0usize, 0.0f64);
    for (i, px) in raw.rgba.chunks_exact(4).enumerate() {
        let (a, b) = (px[0] as f64, reference.mean.rgba[i * 4] as f64);
        assert!(a.is_finite() && (0.0..=1.0).contains(&a), "pixel {i}: {a}");
        // The background is 1 in both; only surfaces count.
        if !judged[i] || (b >= 1.0 && a >= 1.0) {
            continue;
        }
        // Each side's variance of its mean: the reference's own estimate; 256 rays of a
        // value in [0, 1] whose mean is `a` vary by at most a(1 − a) each.
        let var = reference.variance.rgba[i * 4] as f64 + (a * (1.0 - a)).max(1e-4) / 256.0;
        let z = (a - b) / var.sqrt();
        diff += a - b;
        n += 1;
        z2 += z * z;
        z_out += (z.abs() >= 4.5) as usize;
    }
    let (bias, z_var, out) = (diff / n as f64, z2 / n as f64, z_out as f64 / n as f64);
    eprintln!(
        "rtao on {} (falloff {falloff}): bias {bias:+.4} over {n} pixels, z variance {z_var:.3}, {:.2}% beyond 4.5σ",
        scene.name,
        out * 100.0
    );
    assert!(n > 2500, "{n} pixels");
    assert!(bias.abs() <= 0.01, "{}: bias {bias}", scene.name);
    assert!(
        out <= 0.01 && z_var < 2.0,
        "{}: z variance {z_var}, {:.2}% beyond 4.5σ",
        scene.name,
        out * 100.0
    );
}

/// A scene file, as a user writes one, in a fresh folder.
fn scene_file(name: &str, text: &str) -> lightbench::scene::Scene {
    let d = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("lightbench-rt-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let file = d.join(format!("{name}.ron"));
    std::fs::write(&file, text).unwrap();
    lightbench::scene::load(file.to_str().unwrap()).unwrap()
}

/// 8×8-pixel block means of channel-summed values and of their variances of the mean, over
/// the blocks every pixel of which is a surface.
fn blocks(img: &Image, var: Option<&Image>, covered: &[bool]) -> Vec<Option<(f64, f64)>> {
    let (w, h) = (img.width as usize, img.height as usize);
    let mut out = vec![];
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            let (mut sum, mut v, mut all) = (0.0, 0.0, true);
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    let i = (y * w + x) * 4;
                    all &= covered[y * w + x];
                    sum += (0..3).map(|c| img.rgba[i + c] as f64).sum::<f64>();
                    // Channels vary together: the sum's deviation is at most the deviations' sum.
                    v += var.map_or(0.0, |var| (0..3).map(|c| (var.rgba[i + c] as f64).sqrt()).sum::<f64>().powi(2));
                }
            }
            out.push(all.then_some((sum / 64.0, v / 4096.0)));
        }
    }
    out
}

/// `indirect_diffuse = rt` converges to the reference's `indirect_diffuse` block by block
/// (not only on average): at 64², two frames of 64 bounce rays per pixel unblurred
/// (`gi.indirect`; each frame draws other rays) against 256 reference samples, every 8×8
/// block's mean within 4 of its standard errors plus 3% — the ray-traced side's error taken
/// from the two frames' differences, the reference's from its own variance — and within 15%
/// where both sides know it to 5%, on the spot- and
/// sun-lit boxes (RSM's scenes), the box lit only by its ceiling lamp, which RSM leaves
/// without bounce light, and the box with cut-outs (bounce rays through the masked box's
/// holes and by coins through the blended one; the pixels that see neither box).
#[test]
fn ray_traced_indirect_diffuse_matches_the_reference_block_by_block() {
    use lightbench::reference::{Budget, Settings, Term};
    let lamp = "Scene(name: \"lamp_gi\", size: (64, 64), builtin: \"cornell_lamp\", effects: [IndirectDiffuse])\n";
    let mut cut = box_with_cut_outs();
    cut.effects.insert(lightbench_compiler::ir::Effect::IndirectDiffuse);
    let scenes = [
        lightbench::scene::load(gpu_common::root().join("scenes/cornell_spot.ron").to_str().unwrap()).unwrap(),
        lightbench::scene::load(gpu_common::root().join("scenes/cornell_sun.ron").to_str().unwrap()).unwrap(),
        scene_file("lamp_gi", lamp),
        cut,
    ];
    let mut failures = vec![];
    for scene in &scenes {
        let judged = (scene.name == "cut_outs").then(|| beside_the_boxes(scene));
        assert_eq!(scene.size, (64, 64));
        let settings = Settings {
            budget: Budget::Spp(256),
            terms: vec![Term::IndirectDiffuse],
            ..Settings::default()
        };
        let r = lightbench::reference::render(scene, &settings, false);
        let reference = r.term(Term::IndirectDiffuse).unwrap();
        let (first, second) = two_frames_of(scene, ("indirect_diffuse", "rt"), ("gi.rt.rays", "64"), "gi.indirect");
        let compared = compare_blocks((&first, &second), reference, judged.as_deref());
        failures.extend(judge(&scene.name, compared, (30, 30)));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The verdict on one scene's block comparison: every block within 4 standard errors + 3%,
/// the well-known ones within 15%, and at least `(blocks, known)` of each compared; printed.
fn judge(name: &str, (worst, count, ratios): (f64, usize, Vec<f64>), (blocks, known): (usize, usize)) -> Option<String> {
    let spread = (ratios.first().copied().unwrap_or(0.0), ratios.last().copied().unwrap_or(0.0));
    let median = ratios.get(ratios.len() / 2).copied().unwrap_or(0.0);
    eprintln!(
        "{name}: {count} blocks, block ratios {:.3}..{:.3} (median {median:.3}), worst excess {worst:.2}σ",
        spread.0, spread.1
    );
    let bad = count < blocks || worst > 4.0 || ratios.len() < known || spread.0 < 0.85 || spread.1 > 1.15;
    bad.then(|| format!("{name}: {count} blocks, worst {worst:.2}σ beyond 3%, ratios {spread:?}"))
}

/// `resource` after two consecutive frames of `deferred_gi.lbp` with `variant` and `param` set
/// (each frame draws other rays).
fn two_frames_of(scene: &lightbench::scene::Scene, variant: (&str, &str), param: (&str, &str), resource: &str) -> (Image, Image) {
    two_frames_with(scene, "deferred_gi.lbp", &[variant], &[param], resource)
}

/// `resource` after two consecutive frames of a bundled pipeline with `variants` and `params` set.
fn two_frames_with(
    scene: &lightbench::scene::Scene,
    pipeline: &str,
    variants: &[(&str, &str)],
    params: &[(&str, &str)],
    resource: &str,
) -> (Image, Image) {
    let (g, mut ex) = rendered(scene, pipeline, (variants, params), 1);
    let first = ex.read_texture(&g, resource, 0, 0).unwrap();
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap();
    let second = ex.read_texture(&g, resource, 0, 0).unwrap();
    for img in [&first, &second] {
        assert!(
            img.rgba.iter().all(|v| v.is_finite() && *v >= 0.0),
            "{}: NaN, Inf or negative",
            scene.name
        );
    }
    assert_ne!(first.rgba, second.rgba, "each frame draws other rays");
    (first, second)
}

/// Two frames' mean against the reference, 8×8 block by block over the `judged` pixels the
/// frames cover (alpha 1): the largest excess over 3% in standard errors (the frames' from their
/// difference, the reference's from its variance), the blocks compared, and the sorted ratios
/// of the blocks both sides know to 5% (standard error below 5% of the value; where both are
/// noisier the excess alone bounds them). Pixels that see another surface than the
/// reference's camera ray (along geometric edges: off by half and far beyond their noise) are
/// left out, at most 1.5% of them.
fn compare_blocks(
    (first, second): (&Image, &Image),
    reference: &lightbench::reference::TermImage,
    judged: Option<&[bool]>,
) -> (f64, usize, Vec<f64>) {
    let sum = |img: &Image, i: usize| (0..3).map(|c| img.rgba[i * 4 + c] as f64).sum::<f64>();
    let mut covered: Vec<bool> = first.rgba.chunks_exact(4).map(|p| p[3] > 0.5).collect();
    for (c, j) in covered.iter_mut().zip(judged.unwrap_or(&[])) {
        *c &= j;
    }
    let surfaces = covered.iter().filter(|c| **c).count();
    let mut edges = 0;
    for (i, c) in covered.iter_mut().enumerate().filter(|(_, c)| **c) {
        let (a, b, r) = (sum(first, i), sum(second, i), sum(&reference.mean, i));
        let noise = ((a - b).powi(2) / 4.0 + sum(&reference.variance, i)).sqrt();
        if ((a + b) / 2.0 - r).abs() > 0.5 * r + 6.0 * noise + 1e-3 {
            *c = false;
            edges += 1;
        }
    }
    assert!(
        edges as f64 <= 0.015 * surfaces as f64,
        "{edges} of {surfaces} pixels see another surface"
    );
    let (mut mean, mut noise) = (first.clone(), first.clone());
    for i in 0..first.rgba.len() {
        let (a, b) = (first.rgba[i], second.rgba[i]);
        mean.rgba[i] = (a + b) / 2.0;
        // The variance of the two frames' mean: (a − b)² / 4 estimates it.
        noise.rgba[i] = (a - b) * (a - b) / 4.0;
    }
    let ours = blocks(&mean, Some(&noise), &covered);
    let theirs = blocks(&reference.mean, Some(&reference.variance), &covered);
    let (mut worst, mut count, mut ratios) = (0.0f64, 0, vec![]);
    for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        let (Some((a, var_a)), Some((b, var_b))) = (a, b) else { continue };
        let sigma = (var_a + var_b).sqrt();
        let excess = ((a - b).abs() - 0.03 * b) / sigma.max(1e-9);
        if excess > 3.0 {
            eprintln!("  block {k} (x {}, y {}): {a:.4} vs {b:.4}, σ {sigma:.4}", k % 8, k / 8);
        }
        worst = worst.max(excess);
        count += 1;
        if sigma < 0.05 * b {
            ratios.push(a / b);
        }
    }
    ratios.sort_by(f64::total_cmp);
    (worst, count, ratios)
}

/// `reflections = rt` converges to the reference's `indirect_specular` block by block: on the
/// mirror scene (roughness 0.02) and with its floor at roughness 0.5, two frames of 32 rays
/// per pixel (`ssr.color`) against 256 reference samples, every 8×8 block's mean within 4 of
/// its standard errors plus 3%, and within 15% where both sides know it to 5% (as for indirect
/// diffuse; the rough box and wall reflecting the sun's highlight in the mirror are too noisy
/// on both sides to be held closer).
#[test]
fn ray_traced_reflections_match_the_reference_block_by_block() {
    use lightbench::reference::{Budget, Settings, Term};
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("lightbench-rt-mirror-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for model in ["red_box.gltf", "ground.gltf"] {
        std::fs::copy(gpu_common::root().join("scenes").join(model), dir.join(model)).unwrap();
    }
    let mirror = std::fs::read_to_string(gpu_common::root().join("scenes/mirror.gltf")).unwrap();
    assert!(mirror.contains("\"roughnessFactor\": 0.02"));
    std::fs::write(dir.join("mirror.gltf"), &mirror).unwrap();
    std::fs::write(
        dir.join("rough.gltf"),
        mirror.replace("\"roughnessFactor\": 0.02", "\"roughnessFactor\": 0.5"),
    )
    .unwrap();
    let scene_text = std::fs::read_to_string(gpu_common::root().join("scenes/mirror.ron")).unwrap();
    let mut failures = vec![];
    for floor in ["mirror", "rough"] {
        let file = dir.join(format!("{floor}.ron"));
        std::fs::write(
            &file,
            scene_text.replace("(path: \"mirror.gltf\")", &format!("(path: \"{floor}.gltf\")")),
        )
        .unwrap();
        let scene = lightbench::scene::load(file.to_str().unwrap()).unwrap();
        let settings = Settings {
            budget: Budget::Spp(256),
            terms: vec![Term::IndirectSpecular],
            ..Settings::default()
        };
        let r = lightbench::reference::render(&scene, &settings, false);
        let reference = r.term(Term::IndirectSpecular).unwrap();
        let (first, second) = two_frames_of(&scene, ("reflections", "rt"), ("ssr.rt.rays", "32"), "ssr.color");
        let compared = compare_blocks((&first, &second), reference, None);
        failures.extend(judge(floor, compared, (20, 12)));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// `area_lights = rt` is the reference's direct light from emissive surfaces, soft shadows and
/// all: on the box lit only by its ceiling lamp and on the Cornell box with its lamp and a
/// point light (both at 64², ambient 0, `shadows = rt` for the point light), two frames of 64
/// points per pixel unblurred (`area.rt.blur.size` 0) against 256 reference samples of
/// `direct`, every 8×8 block within 4 standard errors + 3%, and within 15% where both sides
/// know it to 5%.
#[test]
fn ray_traced_area_lights_match_the_reference_direct_light() {
    use lightbench::reference::{Budget, Settings, Term};
    let both = "Scene(name: \"lamp_and_point\", size: (64, 64), builtin: \"cornell_lamp\", lights: [Point(position: (0.4, 1.2, 0.3), intensity: 1.0, range: 6.0)])\n";
    let scenes = [
        scene_file(
            "lamp_only",
            "Scene(name: \"lamp_only\", size: (64, 64), builtin: \"cornell_lamp\")\n",
        ),
        scene_file("lamp_and_point", both),
    ];
    let mut failures = vec![];
    for scene in &scenes {
        let settings = Settings {
            budget: Budget::Spp(256),
            terms: vec![Term::Direct],
            ..Settings::default()
        };
        let r = lightbench::reference::render(scene, &settings, false);
        let reference = r.term(Term::Direct).unwrap();
        let params = [
            ("area.rt.samples", "64"),
            ("area.rt.blur.size", "0"),
            ("ambient.color", "(0, 0, 0)"),
        ];
        let variants = [("area_lights", "rt"), ("shadows", "rt")];
        let (mut first, mut second) = two_frames_with(scene, "deferred.lbp", &variants, &params, "hdr");
        // The surfaces: where the G-buffer drew (hdr's alpha is the clear's 1 everywhere).
        for img in [&mut first, &mut second] {
            for (i, px) in reference.mean.rgba.chunks_exact(4).enumerate() {
                img.rgba[i * 4 + 3] = if px[0] + px[1] + px[2] > 0.0 { 1.0 } else { 0.0 };
            }
        }
        let compared = compare_blocks((&first, &second), reference, None);
        failures.extend(judge(&scene.name, compared, (30, 20)));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The ray-traced options over frames (`ao = rtao_temporal`, `indirect_diffuse = rt_temporal`,
/// `area_lights = rt_temporal`) average each frame's rays over a reprojected history: after 16
/// frames of a still camera their estimate is much nearer the reference than one frame's
/// (RMSE over the surfaces below half of one frame's; 16 independent frames would make it a
/// quarter, plus the reference's own noise), and keeps its mean (within 2% of the
/// reference's). Each at its default rays, unblurred where a blur would hide the noise, at 64².
#[test]
fn ray_traced_options_over_frames_converge_towards_the_reference() {
    use lightbench::reference::{Budget, Settings, Term};
    let reference = |scene: &lightbench::scene::Scene, term: Term, ao_radius: f32| {
        let settings = Settings {
            budget: Budget::Spp(512),
            terms: vec![term],
            ao_radius,
            ..Settings::default()
        };
        lightbench::reference::render(scene, &settings, false)
            .term(term)
            .unwrap()
            .mean
            .clone()
    };
    // AO: the occlusion before and after the history (one channel).
    let ao_scene = cornell_ao(64);
    let ao = over_frames(
        &ao_scene,
        "deferred_gi.lbp",
        &[("ao", "rtao_temporal"), ("indirect_diffuse", "off")],
        &[("ao.radius", "0.5"), ("lengths.world", "true"), ("ao.scale", "1")],
        ("ao.raw", "ao.history"),
    );
    let mut failures = vec![];
    failures.extend(judge_over_frames("rtao_temporal", ao, &reference(&ao_scene, Term::Ao, 0.5), 1));
    // Indirect diffuse on the spot-lit box: the bounce light before and after the history.
    let spot = lightbench::scene::load(gpu_common::root().join("scenes/cornell_spot.ron").to_str().unwrap()).unwrap();
    let gi = over_frames(
        &spot,
        "deferred_gi.lbp",
        &[("indirect_diffuse", "rt_temporal")],
        &[],
        ("gi.indirect", "gi.history"),
    );
    failures.extend(judge_over_frames(
        "indirect rt_temporal",
        gi,
        &reference(&spot, Term::IndirectDiffuse, 0.0),
        3,
    ));
    // A second bounce gathers the averaged first: what it adds comes on top of the history.
    let (history, bounced) = over_frames(
        &spot,
        "deferred_gi.lbp",
        &[("indirect_diffuse", "rt_temporal"), ("gi_bounces", "two")],
        &[],
        ("gi.history", "gi.bounced"),
    );
    let below = history
        .rgba
        .chunks(4)
        .zip(bounced.rgba.chunks(4))
        .filter(|(h, b)| (0..3).any(|c| b[c] < h[c] * 0.999 - 1e-4));
    assert_eq!(below.count(), 0, "the second bounce adds to the averaged first");
    let light = |img: &Image| img.rgba.chunks(4).map(|p| (p[0] + p[1] + p[2]) as f64).sum::<f64>();
    assert!(
        light(&bounced) > 1.05 * light(&history),
        "{} vs {}",
        light(&bounced),
        light(&history)
    );
    // Area lights on the lamp-lit box: the emitters' light before and after the history.
    let lamp = scene_file(
        "lamp_frames",
        "Scene(name: \"lamp_frames\", size: (64, 64), builtin: \"cornell_lamp\")\n",
    );
    let area = over_frames(
        &lamp,
        "deferred.lbp",
        &[("area_lights", "rt_temporal")],
        &[],
        ("area.rt", "area.history"),
    );
    // The lamp itself (its emission, which the option leaves to the G-buffer) is not judged.
    let mut truth = reference(&lamp, Term::Direct, 0.0);
    for (i, seen) in lightbench::reference::surfaces_seen(&lamp).into_iter().enumerate() {
        if seen.is_some_and(|m| lamp.materials[lamp.meshes[m].material].emissive != [0.0; 3]) {
            truth.rgba[i * 4..i * 4 + 3].fill(0.0);
        }
    }
    failures.extend(judge_over_frames("area rt_temporal", area, &truth, 3));
    assert!(failures.is_empty(), "{failures:#?}");
}

/// `(one frame, accumulated)`: the resources `resources` names after 16 frames of a bundled
/// pipeline with `variants` and `params` set, the camera still.
fn over_frames(
    scene: &lightbench::scene::Scene,
    pipeline: &str,
    variants: &[(&str, &str)],
    params: &[(&str, &str)],
    (raw, accumulated): (&str, &str),
) -> (Image, Image) {
    let (g, ex) = rendered(scene, pipeline, (variants, params), 16);
    let read = |name: &str| ex.read_texture(&g, name, 0, 0).unwrap();
    (read(raw), read(accumulated))
}

/// `key=value` settings (variant choices or parameter texts).
type Settings<'a> = &'a [(&'a str, &'a str)];

/// A bundled pipeline with `variants` and `params` set, compiled for `scene` and rendered
/// `frames` frames.
fn rendered(
    scene: &lightbench::scene::Scene,
    pipeline: &str,
    (variants, params): (Settings, Settings),
    frames: u32,
) -> (std::sync::MutexGuard<'static, lightbench::gpu::Gpu>, lightbench::gpu::Executor) {
    let g = gpu_common::gpu();
    let pipeline = gpu_common::root().join("pipelines").join(pipeline);
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) = lightbench::render::compile(&g, &pipeline, None, scene, &v).unwrap_or_else(|e| panic!("{e}"));
    let set: Vec<(String, String)> = params.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let params = lightbench::render::parse_params(&exe.plan, &set).unwrap();
    let ex = lightbench::render::render_with(&g, &exe, scene, frames, &params).unwrap();
    (g, ex)
}

/// The verdict on one option over frames against the reference's `truth` (its first
/// `channels` summed; the accumulated side's frame count, in its last channel, left out):
/// RMSE over the surfaces (where the reference is not the background's 0, or AO's open 1
/// everywhere) below half of one frame's, and the mean within 2% of the reference's.
fn judge_over_frames(name: &str, (raw, accumulated): (Image, Image), truth: &Image, channels: usize) -> Option<String> {
    let value = |img: &Image, i: usize| (0..channels).map(|c| img.rgba[i * 4 + c] as f64).sum::<f64>();
    let n = truth.rgba.len() / 4;
    let judged: Vec<usize> = (0..n)
        .filter(|&i| raw.rgba[i * 4 + 3] > 0.5 || channels == 1)
        .filter(|&i| value(truth, i) > 0.0 && !(channels == 1 && value(truth, i) >= 1.0 && value(&raw, i) >= 1.0))
        .collect();
    let stats = |img: &Image| {
        let (mut se, mut sum) = (0.0, 0.0);
        for &i in &judged {
            let v = value(img, i);
            assert!(v.is_finite() && v >= 0.0, "{name}: pixel {i} is {v}");
            se += (v - value(truth, i)).powi(2);
            sum += v;
        }
        ((se / judged.len() as f64).sqrt(), sum / judged.len() as f64)
    };
    let ((e_raw, m_raw), (e_acc, m_acc)) = (stats(&raw), stats(&accumulated));
    let m_ref = judged.iter().map(|&i| value(truth, i)).sum::<f64>() / judged.len() as f64;
    let frames = accumulated.rgba[judged[0] * 4 + if channels == 1 { 1 } else { 3 }];
    eprintln!(
        "{name}: {} pixels, RMSE one frame {e_raw:.4}, {frames} frames {e_acc:.4}; mean one frame {m_raw:.4}, accumulated {m_acc:.4}, reference {m_ref:.4}",
        judged.len()
    );
    let bad = judged.len() < 2000 || e_acc >= 0.5 * e_raw || (m_acc / m_ref - 1.0).abs() > 0.02;
    bad.then(|| format!("{name}: RMSE {e_acc} vs one frame {e_raw}, mean {m_acc} vs {m_ref} (one frame {m_raw})"))
}
