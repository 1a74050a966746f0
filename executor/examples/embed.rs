//! A small winit + wgpu program that owns its window, surface and device and renders a
//! lightbench pipeline into its swap-chain image through the library; saving the pipeline or
//! a shader it uses reloads it while running.
//!
//! ```sh
//! cargo run -p lightbench-executor --example embed -- [--frames N] [--screenshot F.png] [PIPELINE]
//! ```
//! From the repository root; default `pipelines/deferred.lbp` on the built-in Cornell box.
//! `--frames N` closes after N frames; `--screenshot` writes the last swap-chain image.

mod common;

use common::{HostError, Result};
use lightbench_executor::reload::{Outcome, Reloader};
use lightbench_executor::{device, Error, Executor, Gpu, HostOptions};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

/// A full-screen triangle sampling the executor's output: the host's own pass.
const BLIT: &str = r"
@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var linear: sampler;
struct Out { @builtin(position) pos: vec4f, @location(0) uv: vec2f };
@vertex fn vs(@builtin(vertex_index) i: u32) -> Out {
    let uv = vec2f(f32((i << 1u) & 2u), f32(i & 2u));
    return Out(vec4f(uv * vec2f(2.0, -2.0) + vec2f(-1.0, 1.0), 0.0, 1.0), uv);
}
@fragment fn fs(v: Out) -> @location(0) vec4f { return textureSample(image, linear, v.uv); }
";

struct Options {
    pipeline: PathBuf,
    frames: Option<u32>,
    screenshot: Option<PathBuf>,
}

/// What the host keeps once its window exists.
struct Host {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    ex: Executor,
    reloader: Reloader,
    /// The host's copy of the output, which its blit pass samples.
    copy: wgpu::Texture,
    blit: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    start: Instant,
    frames: u32,
}

struct App {
    opts: Options,
    host: Option<Host>,
    result: Result<()>,
}

fn main() {
    let opts = match options() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    let event_loop = EventLoop::new().expect("an event loop (a display: X11 or Wayland)");
    let mut app = App {
        opts,
        host: None,
        result: Ok(()),
    };
    if let Err(e) = event_loop.run_app(&mut app) {
        app.result = Err(HostError::Host(format!("event loop: {e}")));
    }
    if let Err(e) = app.result {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn options() -> Result<Options> {
    let mut opts = Options {
        pipeline: PathBuf::from("pipelines/deferred.lbp"),
        frames: None,
        screenshot: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |what: &str| args.next().ok_or_else(|| HostError::Usage(format!("{a} needs {what}")));
        match a.as_str() {
            "--frames" => {
                let n = value("a count")?;
                opts.frames = Some(n.parse().map_err(|_| HostError::Usage(format!("--frames {n}: not a count")))?);
            }
            "--screenshot" => opts.screenshot = Some(PathBuf::from(value("a file")?)),
            _ if a.starts_with('-') => return Err(HostError::Usage(format!("unknown option {a}"))),
            _ => opts.pipeline = PathBuf::from(a),
        }
    }
    Ok(opts)
}

impl ApplicationHandler for App {
    fn resumed(&mut self, el: &ActiveEventLoop) {
        if self.host.is_none() {
            match Host::new(el, &self.opts) {
                Ok(h) => self.host = Some(h),
                Err(e) => {
                    self.result = Err(e);
                    el.exit();
                }
            }
        }
    }

    fn window_event(&mut self, el: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(host) = self.host.as_mut() else { return };
        match event {
            WindowEvent::CloseRequested => el.exit(),
            WindowEvent::Resized(size) if size.width > 0 && size.height > 0 => {
                host.config.width = size.width;
                host.config.height = size.height;
                host.surface.configure(&host.gpu.device, &host.config);
            }
            WindowEvent::RedrawRequested => {
                let last = self.opts.frames.is_some_and(|n| host.frames + 1 >= n);
                let shot = self.opts.screenshot.as_deref().filter(|_| last);
                if let Err(e) = host.frame(shot) {
                    self.result = Err(e);
                    el.exit();
                } else if last {
                    el.exit();
                } else {
                    host.window.request_redraw();
                }
            }
            _ => {}
        }
    }
}

impl Host {
    fn new(el: &ActiveEventLoop, opts: &Options) -> Result<Host> {
        let scene = lightbench_executor::scene::load::load("cornell")?;
        let (w, h) = scene.size;
        let attrs = Window::default_attributes()
            .with_title("lightbench embedded")
            .with_inner_size(winit::dpi::PhysicalSize::new(w, h));
        let window = Arc::new(el.create_window(attrs).map_err(|e| HostError::Host(format!("window: {e}")))?);

        // The host's instance, surface, adapter and device.
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| HostError::Host(format!("surface: {e}")))?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            compatible_surface: Some(&surface),
            ..Default::default()
        }))
        .map_err(|e| HostError::Host(format!("no adapter for the window: {e}")))?;
        let (dev, queue) = pollster::block_on(adapter.request_device(&device::device_descriptor(&adapter)))
            .map_err(|e| HostError::Host(format!("no device: {e}")))?;
        let config = surface_config(&surface, &adapter, (w, h))?;
        surface.configure(&dev, &config);
        let gpu = Gpu::from_host(adapter, dev, queue, HostOptions { probe: true })?;

        // The pipeline, compiled and watched; its output copied into a texture of the host's.
        let (reloader, exe) = Reloader::new(&gpu, (&opts.pipeline, None), (&scene, None), &[])?;
        let ex = Executor::new(&gpu, &exe, &scene)?;
        let output = ex.output_texture()?;
        let copy = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("host copy of the output"),
            size: output.size(),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: output.format(),
            usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let (blit, bind_group) = blit_pass(&gpu.device, &copy, config.format);
        Ok(Host {
            window,
            surface,
            config,
            gpu,
            ex,
            reloader,
            copy,
            blit,
            bind_group,
            start: Instant::now(),
            frames: 0,
        })
    }

    /// One frame: reload what changed, record the pipeline and the host's blit into one
    /// encoder, submit it, present.
    fn frame(&mut self, screenshot: Option<&std::path::Path>) -> Result<()> {
        match self.reloader.poll(&self.gpu, &mut self.ex, Duration::ZERO) {
            Some(Outcome::Reloaded { latency, .. }) => eprintln!("reloaded in {latency:.1?}"),
            Some(Outcome::Failed { message, .. }) => eprintln!("{message}"),
            Some(Outcome::Rewatched { folders }) => eprintln!("{}", lightbench_executor::reload::rewatched(&folders)),
            None => {}
        }
        let target = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            _ => {
                // Lost or outdated (a resize): configure again and draw the next frame.
                self.surface.configure(&self.gpu.device, &self.config);
                self.window.request_redraw();
                return Ok(());
            }
        };
        let view = target.texture.create_view(&Default::default());
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        let inputs = self.ex.inputs(self.start.elapsed().as_secs_f32());
        self.ex.encode(&self.gpu, &mut enc, &inputs)?;
        let output = self.ex.output_texture()?;
        if output.size() == self.copy.size() {
            enc.copy_texture_to_texture(output.as_image_copy(), self.copy.as_image_copy(), output.size());
        }
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("host blit"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            pass.set_pipeline(&self.blit);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.draw(0..3, 0..1);
        }
        let readback = screenshot.map(|_| copy_out(&self.gpu.device, &mut enc, &target.texture));
        self.ex.submit(&self.gpu, enc)?;
        if let (Some(path), Some(buffer)) = (screenshot, readback) {
            save_png(&self.gpu.device, &buffer, &target.texture, path)?;
        }
        self.gpu.queue.present(target);
        self.frames += 1;
        Ok(())
    }
}

/// The surface's default configuration at the scene's size, with an sRGB format when there is
/// one (the output is sRGB-encoded) and copyable for screenshots where the surface allows.
fn surface_config(surface: &wgpu::Surface, adapter: &wgpu::Adapter, (w, h): (u32, u32)) -> Result<wgpu::SurfaceConfiguration> {
    let mut config = surface
        .get_default_config(adapter, w, h)
        .ok_or_else(|| HostError::Host("the surface is not supported by the adapter".into()))?;
    let caps = surface.get_capabilities(adapter);
    if let Some(srgb) = caps.formats.iter().copied().find(|f| f.is_srgb()) {
        config.format = srgb;
    }
    if caps.usages.contains(wgpu::TextureUsages::COPY_SRC) {
        config.usage |= wgpu::TextureUsages::COPY_SRC;
    }
    Ok(config)
}

fn blit_pass(dev: &wgpu::Device, copy: &wgpu::Texture, format: wgpu::TextureFormat) -> (wgpu::RenderPipeline, wgpu::BindGroup) {
    let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("blit"),
        source: wgpu::ShaderSource::Wgsl(BLIT.into()),
    });
    let pipeline = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("blit"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(format.into())],
        }),
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    });
    let sampler = dev.create_sampler(&wgpu::SamplerDescriptor {
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    let view = copy.create_view(&Default::default());
    let bind_group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("blit"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
        ],
    });
    (pipeline, bind_group)
}

/// Rows padded as buffer copies require.
fn padded_row(width: u32) -> u32 {
    (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

fn copy_out(dev: &wgpu::Device, enc: &mut wgpu::CommandEncoder, tex: &wgpu::Texture) -> wgpu::Buffer {
    let buffer = dev.create_buffer(&wgpu::BufferDescriptor {
        label: Some("screenshot"),
        size: (padded_row(tex.width()) * tex.height()) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    enc.copy_texture_to_buffer(
        tex.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row(tex.width())),
                rows_per_image: None,
            },
        },
        tex.size(),
    );
    buffer
}

fn save_png(dev: &wgpu::Device, buffer: &wgpu::Buffer, tex: &wgpu::Texture, path: &std::path::Path) -> Result<()> {
    let slice = buffer.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    dev.poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::gpu("reading the screenshot", e))?;
    let bgra = matches!(tex.format(), wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb);
    let (w, h, row) = (tex.width(), tex.height(), padded_row(tex.width()) as usize);
    let mapped = slice.get_mapped_range().map_err(|e| Error::gpu("mapping the screenshot", e))?;
    let mut rgba = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h as usize {
        for px in mapped[y * row..y * row + w as usize * 4].chunks(4) {
            let [r, g, b] = if bgra { [px[2], px[1], px[0]] } else { [px[0], px[1], px[2]] };
            rgba.extend([r, g, b, 255].map(|c| c as f32 / 255.0));
        }
    }
    // Written as lightbench writes every file: atomically, through the guarded path.
    let image = lightbench_executor::scene::io::Image {
        width: w,
        height: h,
        rgba,
        srgb: true,
    };
    Ok(image.save(path)?)
}
