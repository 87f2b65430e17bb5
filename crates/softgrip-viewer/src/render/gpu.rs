//! The wgpu side: four pipelines (opaque, blended, lines, x-ray) of one shader
//! (`shaders/lit.wgsl`) drawing lit triangles with a depth buffer, into an
//! offscreen texture read back as an image.
//! Headless, it runs on a software adapter (Mesa's llvmpipe through wgpu's
//! GL backend) with no window and no display.

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::camera::Camera;
use super::geometry::{Drawing, Mesh, Vertex};

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Background colour (linear RGBA).
pub const BACKGROUND: [f64; 4] = [0.96, 0.96, 0.97, 1.0];

/// Why an image could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No graphics adapter was found (the reason wgpu gave).
    #[error(
        "no graphics adapter: {0}. softgrip renders on a software adapter when there is no GPU (Mesa's llvmpipe through EGL; on Debian: apt-get install libegl1 libgl1-mesa-dri)"
    )]
    NoAdapter(String),
    /// The adapter would not open a device (the reason wgpu gave).
    #[error("the graphics device could not be opened: {0}")]
    NoDevice(String),
    /// Copying the rendered image back to memory failed (the reason).
    #[error("reading the image back failed: {0}")]
    Readback(String),
}

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraUniform {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light: [f32; 4],
}

/// The pipeline and its camera uniform, on a given device.
pub struct Pipeline {
    pipeline: wgpu::RenderPipeline,
    /// Alpha-blended, depth-tested but not depth-writing: see-through fingers.
    blended: wgpu::RenderPipeline,
    /// Unlit lines (the wireframe).
    lines: wgpu::RenderPipeline,
    /// Alpha-blended where the depth test fails: what is hidden shows
    /// through (`Drawing::xray`).
    xray: wgpu::RenderPipeline,
    camera_buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

/// A colour texture (RGBA8) and its depth buffer, of one size.
pub struct Target {
    /// The colour texture drawn into (RGBA8, linear).
    pub color: wgpu::Texture,
    /// A view of `color`, the render pass's attachment.
    pub view: wgpu::TextureView,
    depth: wgpu::TextureView,
    /// Width, pixels (at least 1).
    pub width: u32,
    /// Height, pixels (at least 1).
    pub height: u32,
}

impl Target {
    /// A target of `width` x `height` pixels (each at least 1) on `device`.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Target {
        let size = wgpu::Extent3d {
            width: width.max(1),
            height: height.max(1),
            depth_or_array_layers: 1,
        };
        let color = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("color"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let depth = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("depth"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: DEPTH_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let view = color.create_view(&Default::default());
        Target {
            color,
            view,
            depth,
            width: size.width,
            height: size.height,
        }
    }
}

impl Pipeline {
    /// The four pipelines (opaque, lines, blended, x-ray) and the camera uniform on `device`.
    pub fn new(device: &wgpu::Device) -> Pipeline {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lit.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/lit.wgsl").into()),
        });
        let (camera_buffer, layout, bind_group) = camera_binding(device);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let make = |layer: Layer| render_pipeline(device, &pipeline_layout, &shader, layer);
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        let less = wgpu::CompareFunction::Less;
        let pipeline = make(Layer {
            blend: None,
            depth_write: true,
            depth_compare: less,
            topology: triangles,
            fragment: "fs_main",
        });
        let blended = make(Layer {
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            depth_write: false,
            depth_compare: less,
            topology: triangles,
            fragment: "fs_main",
        });
        let lines = make(Layer {
            blend: None,
            depth_write: true,
            depth_compare: less,
            topology: wgpu::PrimitiveTopology::LineList,
            fragment: "fs_flat",
        });
        let xray = make(Layer {
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            depth_write: false,
            depth_compare: wgpu::CompareFunction::Greater,
            topology: triangles,
            fragment: "fs_main",
        });
        Pipeline {
            pipeline,
            blended,
            lines,
            xray,
            camera_buffer,
            bind_group,
        }
    }

    /// Records the drawing of `mesh` seen by `camera` into `target`.
    pub fn draw(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &Target,
        drawing: &Drawing,
        camera: &Camera,
    ) {
        let light = (Vec3::new(0.4, -0.6, 1.0)).normalize();
        let uniform = CameraUniform {
            view_proj: camera
                .view_projection(target.width as f32 / target.height as f32)
                .to_cols_array_2d(),
            eye: camera.eye().extend(1.0).to_array(),
            light: light.extend(0.0).to_array(),
        };
        queue.write_buffer(&self.camera_buffer, 0, bytemuck::bytes_of(&uniform));
        let upload = |mesh: &Mesh| {
            (!mesh.indices.is_empty()).then(|| {
                (
                    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("vertices"),
                        contents: bytemuck::cast_slice(&mesh.vertices),
                        usage: wgpu::BufferUsages::VERTEX,
                    }),
                    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("indices"),
                        contents: bytemuck::cast_slice(&mesh.indices),
                        usage: wgpu::BufferUsages::INDEX,
                    }),
                    mesh.indices.len() as u32,
                )
            })
        };
        let layers = [
            (&self.pipeline, upload(&drawing.opaque)),
            (&self.lines, upload(&drawing.lines)),
            (&self.blended, upload(&drawing.translucent)),
            (&self.xray, upload(&drawing.xray)),
        ];
        let [r, g, b, a] = BACKGROUND;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &target.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        for (pipeline, buffers) in &layers {
            if let Some((vertices, indices, count)) = buffers {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &self.bind_group, &[]);
                pass.set_vertex_buffer(0, vertices.slice(..));
                pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..*count, 0, 0..1);
            }
        }
    }
}

/// How one of the pipelines draws: blending, depth test and write, primitives, fragment shader.
struct Layer {
    /// Alpha blending, or `None` for opaque.
    blend: Option<wgpu::BlendState>,
    /// Whether it writes the depth buffer.
    depth_write: bool,
    /// The depth test passed where the fragment's depth compares so to the buffer's.
    depth_compare: wgpu::CompareFunction,
    /// Triangles or lines.
    topology: wgpu::PrimitiveTopology,
    /// The fragment entry point of `lit.wgsl`: `fs_main` (lit) or `fs_flat` (unlit).
    fragment: &'static str,
}

/// The camera uniform's buffer, its bind group layout and its bind group (binding 0, seen by
/// both the vertex and the fragment stage).
fn camera_binding(device: &wgpu::Device) -> (wgpu::Buffer, wgpu::BindGroupLayout, wgpu::BindGroup) {
    let camera_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("camera"),
        size: std::mem::size_of::<CameraUniform>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("camera"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("camera"),
        layout: &layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: camera_buffer.as_entire_binding(),
        }],
    });
    (camera_buffer, layout, bind_group)
}

/// One render pipeline of `shader` drawing [`Vertex`]es into the colour and depth formats as
/// `layer` says.
fn render_pipeline(
    device: &wgpu::Device,
    pipeline_layout: &wgpu::PipelineLayout,
    shader: &wgpu::ShaderModule,
    layer: Layer,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("lit"),
        layout: Some(pipeline_layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &VERTEX_ATTRIBUTES,
            })],
        },
        primitive: wgpu::PrimitiveState {
            topology: layer.topology,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(layer.depth_write),
            depth_compare: Some(layer.depth_compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some(layer.fragment),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: COLOR_FORMAT,
                blend: layer.blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// [`Vertex`]'s fields as the shader's locations: position, normal, colour.
const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];

/// A device of its own, the pipeline and an offscreen target of a fixed
/// size, read back as images.
pub struct Offscreen {
    device: wgpu::Device,
    queue: wgpu::Queue,
    pipeline: Pipeline,
    target: Target,
    /// Name and backend of the adapter, for reports.
    pub adapter: String,
}

impl Offscreen {
    /// A device on the first adapter found (GL unless `WGPU_BACKEND` says otherwise) and a
    /// target of `width` x `height` pixels.
    pub fn new(width: u32, height: u32) -> Result<Offscreen, RenderError> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            // GL (Mesa's llvmpipe where there is no GPU) unless told
            // otherwise: where Vulkan's lavapipe is also installed, the two
            // differ by a few pixels, and the reference images are GL's.
            descriptor.backends = wgpu::Backends::GL;
        }
        let instance = wgpu::Instance::new(descriptor);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::default(),
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("softgrip offscreen"),
            required_limits:
                wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| RenderError::NoDevice(e.to_string()))?;
        let pipeline = Pipeline::new(&device);
        let target = Target::new(&device, width, height);
        Ok(Offscreen {
            device,
            queue,
            pipeline,
            target,
            adapter: format!("{} ({:?})", info.name, info.backend),
        })
    }

    /// Draws `mesh` seen by `camera` and reads the image back (RGBA8).
    pub fn render(
        &self,
        drawing: &Drawing,
        camera: &Camera,
    ) -> Result<image::RgbaImage, RenderError> {
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        self.pipeline.draw(
            &self.device,
            &self.queue,
            &mut encoder,
            &self.target,
            drawing,
            camera,
        );
        let (width, height) = (self.target.width, self.target.height);
        // Rows of the read-back buffer are padded to 256 bytes.
        let row = 4 * width;
        let padded =
            row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: (padded * height) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            self.target.color.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([encoder.finish()]);
        let slice = readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| RenderError::Readback(e.to_string()))?
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        let data = slice
            .get_mapped_range()
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        let mut pixels = Vec::with_capacity((row * height) as usize);
        for y in 0..height {
            let start = (y * padded) as usize;
            pixels.extend_from_slice(&data[start..start + row as usize]);
        }
        drop(data);
        readback.unmap();
        image::RgbaImage::from_raw(width, height, pixels)
            .ok_or_else(|| RenderError::Readback("image size mismatch".into()))
    }
}
