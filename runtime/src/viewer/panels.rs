//! Sub-stage `panels` of the viewer: the egui side panel — frame time, per-pass costs,
//! parameter widgets made from the Plan's declared parameters, variant choices, lights, and
//! the last error. Widgets only push `Action`s; the viewer applies them.

use super::state::{Action, Viewer};
use lightbench_compiler::ir::{ParamType, ParamValue};

pub fn panels(ui: &mut egui::Ui, v: &Viewer, actions: &mut Vec<Action>) {
    egui::Panel::left("controls").default_size(340.0).show(ui, |ui| {
        egui::ScrollArea::vertical().show(ui, |ui| {
            if let Some(e) = &v.last_error {
                ui.colored_label(egui::Color32::from_rgb(255, 90, 90), format!("error: {e}"));
            }
            ui.label(format!("frame {:.2} ms ({:.0} fps, running mean)", v.frame_ms, 1000.0 / v.frame_ms.max(1e-3)));
            timings(ui, v);
            params(ui, v, actions);
            variants(ui, v, actions);
            lights(ui, v, actions);
            effects(ui, v, actions);
            let mut traced = v.traced.is_some();
            if ui.checkbox(&mut traced, "path traced (T): the GPU reference of this view").changed() {
                actions.push(Action::Trace(traced));
            }
            if let Some(t) = &v.traced {
                ui.label(t.caption());
            }
            if ui.button("screenshot (F12)").clicked() {
                actions.push(Action::Screenshot(format!("lightbench-view-{}-{}.png", std::process::id(), v.frames).into()));
            }
            ui.label("O/P: buffer view · K/L: light or layer · 1–9, 0: light · Q: on/off · arrows: turn it · WASD, Space, Ctrl, Shift, left drag: camera · F12: screenshot · T: path traced");
        });
    });
}

fn timings(ui: &mut egui::Ui, v: &Viewer) {
    egui::CollapsingHeader::new("passes").default_open(true).show(ui, |ui| {
        egui::Grid::new("passes").striped(true).show(ui, |ui| {
            ui.label("pass");
            ui.label("GPU ms");
            ui.label("CPU µs");
            ui.end_row();
            for t in &v.ex.last_timings {
                ui.label(&t.pass);
                ui.label(match (t.reused, t.gpu_ms) {
                    (true, _) => "reused".to_string(),
                    (false, Some(ms)) => format!("{ms:.3}"),
                    (false, None) => "—".to_string(),
                });
                ui.label(format!("{:.1}", t.cpu_encode_us));
                ui.end_row();
            }
        });
    });
}

fn params(ui: &mut egui::Ui, v: &Viewer, actions: &mut Vec<Action>) {
    egui::CollapsingHeader::new("parameters").show(ui, |ui| {
        let values = v.ex.inputs(0.0).params;
        for p in &v.ex.plan().params {
            let now = values.value_of(p).clone();
            let (lo, hi) = (p.min.as_ref().and_then(first), p.max.as_ref().and_then(first));
            let changed = match (&p.ty, &now) {
                (ParamType::Float, ParamValue::Float(x)) => {
                    let mut x = *x;
                    let range = lo.unwrap_or(0.0)..=hi.unwrap_or(1.0);
                    ui.add(egui::Slider::new(&mut x, range).text(&p.name))
                        .changed()
                        .then_some(ParamValue::Float(x))
                }
                (ParamType::Int, ParamValue::Int(x)) => {
                    let mut x = *x;
                    let range = lo.unwrap_or(0.0) as i64..=hi.unwrap_or(64.0) as i64;
                    ui.add(egui::Slider::new(&mut x, range).text(&p.name))
                        .changed()
                        .then_some(ParamValue::Int(x))
                }
                (ParamType::Bool, ParamValue::Bool(b)) => {
                    let mut b = *b;
                    ui.checkbox(&mut b, &p.name).changed().then_some(ParamValue::Bool(b))
                }
                (ParamType::Color, ParamValue::Vec(c)) if c.len() >= 3 => {
                    let mut rgb = [c[0] as f32, c[1] as f32, c[2] as f32];
                    let r = ui.horizontal(|ui| {
                        let r = ui.color_edit_button_rgb(&mut rgb);
                        ui.label(&p.name);
                        r
                    });
                    r.inner.changed().then(|| ParamValue::Vec(rgb.iter().map(|&x| x as f64).collect()))
                }
                (ParamType::Enum(options), ParamValue::Enum(cur)) => {
                    let mut chosen = cur.clone();
                    egui::ComboBox::from_label(&p.name).selected_text(&chosen).show_ui(ui, |ui| {
                        for o in options {
                            ui.selectable_value(&mut chosen, o.clone(), o);
                        }
                    });
                    (chosen != *cur).then_some(ParamValue::Enum(chosen))
                }
                _ => {
                    ui.label(format!("{} = {}", p.name, now.describe()));
                    None
                }
            };
            if let Some(value) = changed {
                actions.push(Action::Param(p.name.clone(), value));
            }
        }
    });
}

/// A parameter bound's first number (a slider's end).
fn first(v: &ParamValue) -> Option<f64> {
    match v {
        ParamValue::Float(x) => Some(*x),
        ParamValue::Int(i) => Some(*i as f64),
        ParamValue::Vec(v) => v.first().copied(),
        _ => None,
    }
}

fn variants(ui: &mut egui::Ui, v: &Viewer, actions: &mut Vec<Action>) {
    egui::CollapsingHeader::new("variants").default_open(true).show(ui, |ui| {
        for c in &v.ex.plan().variants {
            let mut chosen = c.option.clone();
            let options = v
                .options
                .iter()
                .find(|(name, _)| *name == c.variant)
                .map(|(_, o)| o.as_slice())
                .unwrap_or(&[]);
            egui::ComboBox::from_label(&c.variant).selected_text(&chosen).show_ui(ui, |ui| {
                for (o, missing) in options {
                    // Options the adapter cannot run are shown disabled, with what they need.
                    let r = ui.add_enabled(missing.is_none(), egui::Button::selectable(chosen == *o, o.as_str()));
                    if r.clicked() {
                        chosen = o.clone();
                    }
                    if let Some(m) = missing {
                        r.on_disabled_hover_text(m.as_str());
                    }
                }
            });
            if let Some(r) = &c.reason {
                ui.small(r);
            }
            if chosen != c.option {
                actions.push(Action::Variant(c.variant.clone(), chosen));
            }
        }
    });
}

fn lights(ui: &mut egui::Ui, v: &Viewer, actions: &mut Vec<Action>) {
    use lightbench_compiler::ir::LightKind;
    egui::CollapsingHeader::new("lights").default_open(true).show(ui, |ui| {
        for (i, l) in v.scene.lights.iter().enumerate() {
            let selected = i == v.light;
            if ui
                .selectable_label(selected, format!("{} {:?}{}", i + 1, l.kind, if l.on { "" } else { " (off)" }))
                .clicked()
            {
                actions.push(Action::SelectLight(i));
            }
            if selected {
                let mut edited = l.clone();
                light_editor(ui, &mut edited);
                if edited != *l {
                    actions.push(Action::SetLight(i, Box::new(edited)));
                }
            }
        }
        ui.horizontal(|ui| {
            for kind in LightKind::ALL.into_iter().filter(|k| k.punctual()) {
                if ui.button(format!("+ {}", kind.name())).clicked() {
                    actions.push(Action::AddLight(kind));
                }
            }
            if ui.button("remove").clicked() {
                actions.push(Action::RemoveLight);
            }
        });
    });
}

/// Every field of a light as widgets.
fn light_editor(ui: &mut egui::Ui, l: &mut crate::scene::Light) {
    use lightbench_compiler::ir::LightKind;
    egui::ComboBox::from_label("kind").selected_text(l.kind.name()).show_ui(ui, |ui| {
        for k in LightKind::ALL {
            ui.selectable_value(&mut l.kind, k, k.name());
        }
    });
    ui.checkbox(&mut l.on, "on");
    ui.checkbox(&mut l.shadows, "shadows");
    let mut c = l.color.to_array();
    ui.horizontal(|ui| {
        ui.color_edit_button_rgb(&mut c);
        ui.label("colour");
    });
    l.color = glam::Vec3::from(c);
    ui.add(egui::Slider::new(&mut l.intensity, 0.0..=50.0).text("intensity"));
    if l.kind != LightKind::Directional {
        vec3(ui, "position", &mut l.position);
        ui.add(egui::Slider::new(&mut l.range, 0.1..=100.0).text("range"));
    }
    if l.kind != LightKind::Point {
        vec3(ui, "direction", &mut l.direction);
    }
    if l.kind == LightKind::Spot {
        ui.add(egui::Slider::new(&mut l.outer_angle, 1.0..=89.0).text("outer cone °"));
        ui.add(egui::Slider::new(&mut l.inner_angle, 0.0..=l.outer_angle).text("inner cone °"));
    }
}

fn vec3(ui: &mut egui::Ui, label: &str, v: &mut glam::Vec3) {
    ui.horizontal(|ui| {
        for c in [&mut v.x, &mut v.y, &mut v.z] {
            ui.add(egui::DragValue::new(c).speed(0.05));
        }
        ui.label(label);
    });
}

fn effects(ui: &mut egui::Ui, v: &Viewer, actions: &mut Vec<Action>) {
    use lightbench_compiler::ir::Effect;
    egui::CollapsingHeader::new("effects").show(ui, |ui| {
        for e in Effect::ALL {
            let mut on = v.scene.effects.contains(&e);
            if ui.checkbox(&mut on, e.name()).changed() {
                actions.push(Action::Effect(e, on));
            }
        }
    });
}
