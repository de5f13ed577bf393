//! GPU drawing of the 3D view through an egui paint callback (wgpu): the mesh is drawn into an
//! offscreen colour + depth target with 4× MSAA, resolved, then copied into egui's render pass
//! (which has no depth buffer). On a software rasterizer (a CPU adapter: lavapipe under Xvfb, a
//! machine without a GPU) the target has one sample: MSAA multiplies its fill work by four, and
//! there the frame that shows a new picture is what a slider move waits for. Vertex data is
//! uploaded only when the mesh version changes; a camera move only rewrites the 96-byte uniform
//! block. Each viewport of a frame (one, or two side by side) has its own slot: targets, vertex
//! buffer and uniforms, since egui-wgpu prepares every callback of a frame before it paints any.

use crate::mesh_build::{MeshData, Vertex};
use bytemuck::{Pod, Zeroable};
use eframe::egui_wgpu::{self, wgpu};
use std::sync::Arc;

/// Samples of the 3D target on a GPU.
const SAMPLES: u32 = 4;
const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The uniform block of mesh.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Uniforms {
    /// Column-major view-projection matrix.
    pub view_proj: [[f32; 4]; 4],
    /// Direction towards the light.
    pub light: [f32; 4],
    /// x: 1 with a section.
    pub flags: [f32; 4],
}

/// One frame of one viewport of the 3D view: the mesh (shared, versioned) and the camera.
pub struct SceneCallback {
    /// The viewport's slot (0: the current configuration; 1: the pinned one beside it).
    pub slot: usize,
    /// The mesh to draw.
    pub mesh: Arc<MeshData>,
    /// Its version: the vertex buffer is re-uploaded when it changes.
    pub version: u64,
    /// Camera and lighting.
    pub uniforms: Uniforms,
    /// Size of the view in physical pixels.
    pub size_px: [u32; 2],
    /// Background colour (sRGB).
    pub background: [f32; 3],
}

struct Targets {
    size: [u32; 2],
    /// The multisampled colour target (None with one sample: drawn into `resolved` directly).
    msaa: Option<wgpu::TextureView>,
    resolved: wgpu::TextureView,
    depth: wgpu::TextureView,
    blit_group: wgpu::BindGroup,
}

/// What one viewport keeps on the GPU between frames.
struct Slot {
    uniforms: wgpu::Buffer,
    uniform_group: wgpu::BindGroup,
    vertices: Option<wgpu::Buffer>,
    vertex_count: u32,
    version: Option<u64>,
    targets: Option<Targets>,
    /// What the resolved picture shows now (mesh version, camera, size): an unchanged frame
    /// is not drawn again, only copied.
    drawn: Option<(u64, Uniforms, [u32; 2])>,
}

/// GPU objects of the view, kept in egui-wgpu's callback resources: the pipelines, shared, and
/// one [`Slot`] per viewport, made when a viewport is first drawn.
pub struct Resources {
    mesh_pipeline: wgpu::RenderPipeline,
    blit_pipeline: wgpu::RenderPipeline,
    blit_layout: wgpu::BindGroupLayout,
    uniform_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// Samples per pixel of the 3D target ([`samples_for`]).
    samples: u32,
    slots: Vec<Slot>,
}

/// Samples per pixel of the 3D target on an adapter of this type: 4 on a GPU, 1 on a CPU
/// (software rasterization).
pub fn samples_for(device_type: wgpu::DeviceType) -> u32 {
    match device_type {
        wgpu::DeviceType::Cpu => 1,
        _ => SAMPLES,
    }
}

/// Creates the pipelines once, for egui's target format, and stores them.
pub fn install(rs: &egui_wgpu::RenderState) {
    let device = &rs.device;
    let samples = samples_for(rs.adapter.get_info().device_type);
    let mesh_shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("lopin mesh"),
        source: wgpu::ShaderSource::Wgsl(include_str!("mesh.wgsl").into()),
    });
    let blit_shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("lopin blit"),
        source: wgpu::ShaderSource::Wgsl(include_str!("blit.wgsl").into()),
    });
    let uniform_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("lopin uniforms"),
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
    let blit_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("lopin blit"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    });
    let mesh_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("lopin mesh"),
        bind_group_layouts: &[Some(&uniform_layout)],
        immediate_size: 0,
    });
    let blit_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("lopin blit"),
        bind_group_layouts: &[Some(&blit_layout)],
        immediate_size: 0,
    });
    let attributes = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32, 4 => Float32
    ];
    let mesh_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("lopin mesh"),
        layout: Some(&mesh_pipeline_layout),
        vertex: wgpu::VertexState {
            module: &mesh_shader,
            entry_point: Some("vs_mesh"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &attributes,
            })],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module: &mesh_shader,
            entry_point: Some("fs_mesh"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: COLOR,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    });
    let blit_entry = if rs.target_format.is_srgb() {
        "fs_blit_linear"
    } else {
        "fs_blit"
    };
    let blit_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("lopin blit"),
        layout: Some(&blit_pipeline_layout),
        vertex: wgpu::VertexState {
            module: &blit_shader,
            entry_point: Some("vs_blit"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &blit_shader,
            entry_point: Some(blit_entry),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: rs.target_format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    });
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("lopin blit"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    rs.renderer.write().callback_resources.insert(Resources {
        mesh_pipeline,
        blit_pipeline,
        blit_layout,
        uniform_layout,
        sampler,
        samples,
        slots: Vec::new(),
    });
}

impl Slot {
    fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> Slot {
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lopin uniforms"),
            size: std::mem::size_of::<Uniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let uniform_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lopin uniforms"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        Slot {
            uniforms,
            uniform_group,
            vertices: None,
            vertex_count: 0,
            version: None,
            targets: None,
            drawn: None,
        }
    }

    fn ensure_targets(
        &mut self,
        device: &wgpu::Device,
        size: [u32; 2],
        blit_layout: &wgpu::BindGroupLayout,
        sampler: &wgpu::Sampler,
        samples: u32,
    ) {
        if self.targets.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        let extent = wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        };
        let texture = |label, format, samples, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let msaa = (samples > 1).then(|| texture("lopin msaa", COLOR, samples, attach));
        let resolved = texture(
            "lopin picture",
            COLOR,
            1,
            attach | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let depth = texture("lopin depth", DEPTH, samples, attach);
        let blit_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lopin blit"),
            layout: blit_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&resolved),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
            ],
        });
        self.targets = Some(Targets {
            size,
            msaa,
            resolved,
            depth,
            blit_group,
        });
    }

    fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, mesh: &MeshData) {
        let bytes: &[u8] = bytemuck::cast_slice(&mesh.vertices);
        let fits = self
            .vertices
            .as_ref()
            .is_some_and(|b| b.size() >= bytes.len() as u64);
        if !fits {
            self.vertices = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lopin vertices"),
                size: (bytes.len() as u64).max(64).next_power_of_two(),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        if let Some(b) = &self.vertices {
            if !bytes.is_empty() {
                queue.write_buffer(b, 0, bytes);
            }
        }
        self.vertex_count = mesh.vertices.len() as u32;
    }
}

impl egui_wgpu::CallbackTrait for SceneCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen: &egui_wgpu::ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        let Some(res) = resources.get_mut::<Resources>() else {
            return Vec::new();
        };
        while res.slots.len() <= self.slot {
            let slot = Slot::new(device, &res.uniform_layout);
            res.slots.push(slot);
        }
        let size = [self.size_px[0].max(1), self.size_px[1].max(1)];
        let r = &mut res.slots[self.slot];
        r.ensure_targets(device, size, &res.blit_layout, &res.sampler, res.samples);
        let frame = (self.version, self.uniforms, size);
        if r.drawn == Some(frame) {
            return Vec::new();
        }
        r.drawn = Some(frame);
        if r.version != Some(self.version) {
            r.upload(device, queue, &self.mesh);
            r.version = Some(self.version);
        }
        queue.write_buffer(&r.uniforms, 0, bytemuck::bytes_of(&self.uniforms));
        let Some(t) = &r.targets else {
            return Vec::new();
        };
        let [br, bg, bb] = self.background.map(f64::from);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("lopin 3d"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: t.msaa.as_ref().unwrap_or(&t.resolved),
                depth_slice: None,
                resolve_target: t.msaa.as_ref().map(|_| &t.resolved),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: br,
                        g: bg,
                        b: bb,
                        a: 1.0,
                    }),
                    // the multisampled target is resolved and dropped; a single-sampled one is
                    // the picture
                    store: if t.msaa.is_some() {
                        wgpu::StoreOp::Discard
                    } else {
                        wgpu::StoreOp::Store
                    },
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let (Some(vb), true) = (&r.vertices, r.vertex_count > 0) {
            pass.set_pipeline(&res.mesh_pipeline);
            pass.set_bind_group(0, &r.uniform_group, &[]);
            pass.set_vertex_buffer(0, vb.slice(..));
            pass.draw(0..r.vertex_count, 0..1);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        render_pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        let Some(r) = resources.get::<Resources>() else {
            return;
        };
        let Some(t) = r.slots.get(self.slot).and_then(|s| s.targets.as_ref()) else {
            return;
        };
        render_pass.set_pipeline(&r.blit_pipeline);
        render_pass.set_bind_group(0, &t.blit_group, &[]);
        render_pass.draw(0..3, 0..1);
    }
}
