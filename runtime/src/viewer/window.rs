//! Sub-stage `window` of the viewer: a winit window with a wgpu surface, egui panels around
//! the shown image, and keys and widgets turned into `Action`s (seed 000 ch. 8's controls).

use super::state::{Action, Viewer};
use super::Options;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use std::collections::VecDeque;
use std::sync::Arc;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use super::script::Step;

struct Running {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    viewer: Viewer,
    egui: egui::Context,
    egui_state: egui_winit::State,
    renderer: egui_wgpu::Renderer,
    /// The shown image when it needs the display mapping (read back, mapped on the CPU).
    texture: Option<egui::TextureHandle>,
    /// The shown image when the GPU shows it as it is: the window's copy of it, registered
    /// with egui (the executor's texture is not sampleable, and is re-created on reload).
    native: Option<(wgpu::Texture, egui::TextureId)>,
    looking: bool,
    last_cursor: Option<(f64, f64)>,
}

pub struct App {
    opts: Options,
    script: VecDeque<Step>,
    wait_frames: u32,
    running: Option<Running>,
    pub result: Result<()>,
}

impl App {
    pub fn new(opts: Options, script: Vec<Step>) -> App {
        App {
            opts,
            script: script.into(),
            wait_frames: 0,
            running: None,
            result: Ok(()),
        }
    }

    fn start(&mut self, el: &ActiveEventLoop) -> Result<Running> {
        let (w, h) = self.opts.scene.size;
        let attrs = Window::default_attributes()
            .with_title("lightbench view")
            .with_inner_size(winit::dpi::PhysicalSize::new(w + 360, h.max(480)));
        let window = Arc::new(
            el.create_window(attrs)
                .map_err(|e| Error::Usage(format!("cannot open a window: {e}")))?,
        );
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| Error::Usage(format!("cannot draw into the window: {e}")))?;
        let gpu = Gpu::for_surface(&instance, &surface)?;
        eprintln!("{}", gpu.describe());
        let size = window.inner_size();
        let config = surface
            .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| Error::Usage("the window's surface has no usable format".into()))?;
        surface.configure(&gpu.device, &config);
        let mut viewer = Viewer::new(
            &gpu,
            (self.opts.workspace.clone(), &self.opts.pipeline, self.opts.shaders.as_deref()),
            self.opts.scene.clone(),
            &self.opts.variants,
        )?;
        if !self.opts.pipeline.starts_with(crate::bundled::ROOT) {
            viewer.watch(&gpu, (self.opts.scene_file.as_deref(), &self.opts.effects))?;
            viewer.keep_models(std::mem::take(&mut self.opts.models));
        }
        let egui = egui::Context::default();
        let egui_state = egui_winit::State::new(egui.clone(), egui::ViewportId::ROOT, &window, None, None, None);
        let renderer = egui_wgpu::Renderer::new(&gpu.device, config.format, egui_wgpu::RendererOptions::default());
        Ok(Running {
            window,
            surface,
            config,
            gpu,
            viewer,
            egui,
            egui_state,
            renderer,
            texture: None,
            native: None,
            looking: false,
            last_cursor: None,
        })
    }

    /// The next scripted action, once the frames asked for have been rendered; `Some(None)`
    /// when the script is over (the window then closes).
    fn next_step(&mut self) -> Option<Option<(String, String)>> {
        if self.wait_frames > 0 {
            self.wait_frames -= 1;
            return None;
        }
        match self.script.pop_front() {
            Some(Step::Frames(n)) => {
                self.wait_frames = n;
                None
            }
            Some(Step::Line(l, at)) => Some(Some((l, at))),
            None if self.opts.scripted => Some(None),
            None => None,
        }
    }
}

/// Keys of seed 000 ch. 8 and the buffer views.
fn key_action(code: KeyCode) -> Option<Action> {
    Some(match code {
        KeyCode::KeyO => Action::PrevView,
        KeyCode::KeyP => Action::NextView,
        KeyCode::KeyK => Action::PrevSlice,
        KeyCode::KeyL => Action::NextSlice,
        KeyCode::KeyQ => Action::ToggleLight,
        KeyCode::KeyT => Action::ToggleTrace,
        KeyCode::ArrowLeft => Action::RotateLight(5.0, 0.0),
        KeyCode::ArrowRight => Action::RotateLight(-5.0, 0.0),
        KeyCode::ArrowUp => Action::RotateLight(0.0, 5.0),
        KeyCode::ArrowDown => Action::RotateLight(0.0, -5.0),
        KeyCode::F12 => Action::Screenshot(format!("lightbench-view-{}.png", std::process::id()).into()),
        KeyCode::Digit0 => Action::SelectLight(9),
        d @ (KeyCode::Digit1
        | KeyCode::Digit2
        | KeyCode::Digit3
        | KeyCode::Digit4
        | KeyCode::Digit5
        | KeyCode::Digit6
        | KeyCode::Digit7
        | KeyCode::Digit8
        | KeyCode::Digit9) => Action::SelectLight(d as usize - KeyCode::Digit1 as usize),
        _ => return None,
    })
}

impl Running {
    /// WASD / Space / Left Ctrl held: move the camera (Left Shift: faster).
    fn camera_keys(&mut self) {
        let held = |k| self.egui.input(|i| i.key_down(k));
        let shift = self.egui.input(|i| i.modifiers.shift);
        let step = if shift { 0.15 } else { 0.05 };
        let mut d = glam::Vec3::ZERO;
        for (key, v) in [
            (egui::Key::W, glam::Vec3::Z),
            (egui::Key::S, -glam::Vec3::Z),
            (egui::Key::D, glam::Vec3::X),
            (egui::Key::A, -glam::Vec3::X),
            (egui::Key::Space, glam::Vec3::Y),
        ] {
            if held(key) {
                d += v;
            }
        }
        if self.egui.input(|i| i.modifiers.ctrl) {
            d -= glam::Vec3::Y;
        }
        if d != glam::Vec3::ZERO {
            let _ = self.viewer.apply(&self.gpu, Action::Move(d * step));
        }
    }

    fn redraw(&mut self, line: Option<(String, String)>) -> Result<()> {
        if let Some((l, at)) = line {
            // A scripted action that fails stops the script: the error is the result, located.
            super::script::run_line(&mut self.viewer, &self.gpu, &l, &at)?;
        }
        self.camera_keys();
        self.viewer.poll_reload(&self.gpu);
        self.viewer.frame(&self.gpu)?;
        let (id, (w, h), caption) = self.shown_image()?;
        let input = self.egui_state.take_egui_input(&self.window);
        let mut actions = vec![];
        let output = self.egui.run_ui(input, |ui| {
            super::panels::panels(ui, &self.viewer, &mut actions);
            egui::CentralPanel::default_margins().show(ui, |ui| {
                ui.label(&caption);
                ui.image((id, egui::vec2(w as f32, h as f32)));
            });
        });
        for a in actions {
            let _ = self.viewer.apply(&self.gpu, a);
        }
        self.egui_state.handle_platform_output(&self.window, output.platform_output);
        self.paint(output.shapes, output.textures_delta, output.pixels_per_point)
    }

    /// The shown image as an egui texture: copied on the GPU when it can be shown as it is
    /// (the output), else read back and mapped for display.
    fn shown_image(&mut self) -> Result<(egui::TextureId, (u32, u32), String)> {
        if let Some((src, layer, caption)) = self.viewer.shown_texture()? {
            let size = src.size();
            let id = self.native_copy(&src, layer);
            return Ok((id, (size.width, size.height), caption));
        }
        let (w, h, rgb, caption) = self.viewer.view_image(&self.gpu)?;
        let image = egui::ColorImage::from_rgb([w as usize, h as usize], &rgb);
        let t = match &mut self.texture {
            Some(t) => {
                t.set(image, egui::TextureOptions::NEAREST);
                t
            }
            None => self
                .texture
                .insert(self.egui.load_texture("view", image, egui::TextureOptions::NEAREST)),
        };
        Ok((t.id(), (w, h), caption))
    }

    /// Copy layer `layer` of `src` into the window's sampleable texture (made, or re-made at a
    /// new size or format, and registered with egui) and return its egui id.
    fn native_copy(&mut self, src: &wgpu::Texture, layer: u32) -> egui::TextureId {
        let (device, size) = (&self.gpu.device, src.size());
        let fits = |t: &wgpu::Texture| t.width() == size.width && t.height() == size.height && t.format() == src.format();
        if !self.native.as_ref().is_some_and(|(t, _)| fits(t)) {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("shown image"),
                size: wgpu::Extent3d {
                    depth_or_array_layers: 1,
                    ..size
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: src.format(),
                usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            });
            let view = texture.create_view(&Default::default());
            let id = match self.native.take() {
                Some((_, id)) => {
                    self.renderer
                        .update_egui_texture_from_wgpu_texture(device, &view, wgpu::FilterMode::Nearest, id);
                    id
                }
                None => self.renderer.register_native_texture(device, &view, wgpu::FilterMode::Nearest),
            };
            self.native = Some((texture, id));
        }
        let (dst, id) = self.native.as_ref().expect("made above");
        let mut enc = device.create_command_encoder(&Default::default());
        enc.copy_texture_to_texture(
            wgpu::TexelCopyTextureInfo {
                texture: src,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
                aspect: wgpu::TextureAspect::All,
            },
            dst.as_image_copy(),
            wgpu::Extent3d {
                depth_or_array_layers: 1,
                ..size
            },
        );
        self.gpu.queue.submit([enc.finish()]);
        *id
    }

    fn paint(&mut self, shapes: Vec<egui::epaint::ClippedShape>, mut delta: egui::TexturesDelta, ppp: f32) -> Result<()> {
        // egui's texture changes are applied every frame, drawn or not (it asserts so).
        for (id, deltas) in delta.set.drain() {
            for d in deltas {
                self.renderer.update_texture(&self.gpu.device, &self.gpu.queue, id, &d);
            }
        }
        let freed: Vec<egui::TextureId> = delta.free.drain().collect();
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            _ => {
                self.surface.configure(&self.gpu.device, &self.config);
                for id in &freed {
                    self.renderer.free_texture(id);
                }
                return Ok(());
            }
        };
        let (gpu, renderer) = (&self.gpu, &mut self.renderer);
        let jobs = self.egui.tessellate(shapes, ppp);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: ppp,
        };
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let mut cmds = renderer.update_buffers(&gpu.device, &gpu.queue, &mut enc, &jobs, &screen);
        let view = frame.texture.create_view(&Default::default());
        {
            let pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            renderer.render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        cmds.push(enc.finish());
        gpu.queue.submit(cmds);
        gpu.queue.present(frame);
        for id in &freed {
            renderer.free_texture(id);
        }
        Ok(())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, el: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.start(el) {
            Ok(r) => self.running = Some(r),
            Err(e) => {
                self.result = Err(e);
                el.exit();
            }
        }
    }

    fn window_event(&mut self, el: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(r) = self.running.as_mut() else { return };
        let consumed = r.egui_state.on_window_event(&r.window, &event).consumed;
        match event {
            WindowEvent::CloseRequested => el.exit(),
            WindowEvent::Resized(size) => {
                r.config.width = size.width.max(1);
                r.config.height = size.height.max(1);
                r.surface.configure(&r.gpu.device, &r.config);
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } if !consumed => {
                r.looking = state == ElementState::Pressed;
                r.last_cursor = None;
            }
            WindowEvent::CursorMoved { position, .. } if r.looking => {
                if let Some((x, y)) = r.last_cursor {
                    let _ = r
                        .viewer
                        .apply(&r.gpu, Action::Look(-(position.x - x) as f32 * 0.2, -(position.y - y) as f32 * 0.2));
                }
                r.last_cursor = Some((position.x, position.y));
            }
            WindowEvent::KeyboardInput { event, .. } if !consumed && event.state == ElementState::Pressed => {
                let action = match event.physical_key {
                    PhysicalKey::Code(c) => key_action(c),
                    _ => None,
                };
                if let Some(a) = action {
                    let _ = r.viewer.apply(&r.gpu, a);
                }
            }
            WindowEvent::RedrawRequested => {
                let step = self.next_step();
                let Some(r) = self.running.as_mut() else { return };
                match step {
                    Some(None) => el.exit(),
                    Some(Some(a)) => {
                        if let Err(e) = r.redraw(Some(a)) {
                            self.result = Err(e);
                            el.exit();
                        }
                    }
                    None => {
                        if let Err(e) = r.redraw(None) {
                            self.result = Err(e);
                            el.exit();
                        }
                    }
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(r) = &self.running {
            r.window.request_redraw();
        }
    }
}
