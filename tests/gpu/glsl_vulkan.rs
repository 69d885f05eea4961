//! The GLSL translation of the lookup (`clothbake wgsl --lang glsl`) as a Vulkan engine runs
//! it: compiled to SPIR-V by Khronos' glslangValidator and dispatched through Vulkan itself
//! (ash) on the first device the Vulkan loader lists (lavapipe in CI), with the table's textures as
//! the combined image samplers the GLSL declares, at its bindings, and the kernel's buffers
//! at 0 and 1. wgpu cannot run it: it binds textures and samplers separately, and naga's GLSL
//! passes combined samplers to functions, which no rewrite to separate ones survives. Pair by
//! pair against the WGSL lookup run by wgpu on the same table.

use crate::common::*;

use ash::vk;
use clothbake::bake::bake;
use clothbake::evaluator::table::gpu::GpuTable;
use clothbake::gpu::evaluate_pairs;
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::table::shader_language::{ShaderLanguage, lookup_shader};
use clothbake::table::{Layout, Table, TextureData};
use glam::Vec3;
use std::process::Command;

/// Largest relative difference accepted between the GLSL and the WGSL lookup, where F is
/// above 1e-4 of its largest value. Both are the same f32 arithmetic compiled by two
/// compilers for one driver, fetching the same f16 texels through the same filter: measured
/// 0 on lavapipe (every pair of every layout bit-identical); the bound allows another
/// driver's contraction of a few multiply-adds (a few ulps on a quantity that cancels by
/// 10–100×).
const BOUND: f64 = 1e-5;
/// Pairs per set (uniform and highlight).
const PAIRS: usize = 4000;
/// `@workgroup_size` of the kernel (shaders/gpu/eval_pairs.wgsl).
const WORKGROUP_SIZE: u32 = 64;

/// A Vulkan device with a compute queue, and what the test allocates on it.
struct Vulkan {
    _entry: ash::Entry,
    instance: ash::Instance,
    device: ash::Device,
    queue: vk::Queue,
    pool: vk::CommandPool,
    memory: vk::PhysicalDeviceMemoryProperties,
    name: String,
}

impl Vulkan {
    fn new() -> Self {
        // SAFETY: plain Vulkan calls in the order the specification requires; every handle
        // is used while its parent lives and destroyed in `Drop` or by `Evaluation::drop`.
        unsafe {
            let entry = ash::Entry::load().expect("the Vulkan loader (Debian: libvulkan1)");
            let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_1);
            let instance = entry
                .create_instance(
                    &vk::InstanceCreateInfo::default().application_info(&app),
                    None,
                )
                .expect("Vulkan instance");
            let (physical, family) = instance
                .enumerate_physical_devices()
                .expect("physical devices")
                .into_iter()
                .find_map(|p| {
                    instance
                        .get_physical_device_queue_family_properties(p)
                        .iter()
                        .position(|q| q.queue_flags.contains(vk::QueueFlags::COMPUTE))
                        .map(|f| (p, f as u32))
                })
                .expect("a Vulkan device with a compute queue (Debian: mesa-vulkan-drivers)");
            let properties = instance.get_physical_device_properties(physical);
            let name = properties
                .device_name_as_c_str()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let priorities = [1.0];
            let queues = [vk::DeviceQueueCreateInfo::default()
                .queue_family_index(family)
                .queue_priorities(&priorities)];
            let device = instance
                .create_device(
                    physical,
                    &vk::DeviceCreateInfo::default().queue_create_infos(&queues),
                    None,
                )
                .expect("Vulkan device");
            let queue = device.get_device_queue(family, 0);
            let pool = device
                .create_command_pool(
                    &vk::CommandPoolCreateInfo::default().queue_family_index(family),
                    None,
                )
                .unwrap();
            let memory = instance.get_physical_device_memory_properties(physical);
            Self {
                _entry: entry,
                instance,
                device,
                queue,
                pool,
                memory,
                name,
            }
        }
    }

    /// Memory for `requirements` with `flags` (host-visible and coherent for buffers the test
    /// reads and writes; anything for images).
    fn allocate(
        &self,
        requirements: vk::MemoryRequirements,
        flags: vk::MemoryPropertyFlags,
    ) -> vk::DeviceMemory {
        let index = (0..self.memory.memory_type_count)
            .find(|&i| {
                requirements.memory_type_bits & (1 << i) != 0
                    && self.memory.memory_types[i as usize]
                        .property_flags
                        .contains(flags)
            })
            .expect("a memory type");
        // SAFETY: see `new`.
        unsafe {
            self.device
                .allocate_memory(
                    &vk::MemoryAllocateInfo::default()
                        .allocation_size(requirements.size)
                        .memory_type_index(index),
                    None,
                )
                .unwrap()
        }
    }

    /// A host-visible buffer of `size` bytes holding `contents` (zeros after them).
    fn buffer(
        &self,
        size: usize,
        usage: vk::BufferUsageFlags,
        contents: &[u8],
    ) -> (vk::Buffer, vk::DeviceMemory) {
        // SAFETY: see `new`.
        unsafe {
            let buffer = self
                .device
                .create_buffer(
                    &vk::BufferCreateInfo::default()
                        .size(size as u64)
                        .usage(usage),
                    None,
                )
                .unwrap();
            let memory = self.allocate(
                self.device.get_buffer_memory_requirements(buffer),
                vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
            );
            self.device.bind_buffer_memory(buffer, memory, 0).unwrap();
            let mapped = self
                .device
                .map_memory(memory, 0, size as u64, vk::MemoryMapFlags::empty())
                .unwrap() as *mut u8;
            std::ptr::write_bytes(mapped, 0, size);
            std::ptr::copy_nonoverlapping(contents.as_ptr(), mapped, contents.len());
            self.device.unmap_memory(memory);
            (buffer, memory)
        }
    }

    /// Records `record` into a command buffer, submits it and waits for it.
    fn submit(&self, record: impl FnOnce(vk::CommandBuffer)) {
        // SAFETY: see `new`.
        unsafe {
            let command = self
                .device
                .allocate_command_buffers(
                    &vk::CommandBufferAllocateInfo::default()
                        .command_pool(self.pool)
                        .command_buffer_count(1),
                )
                .unwrap()[0];
            self.device
                .begin_command_buffer(command, &vk::CommandBufferBeginInfo::default())
                .unwrap();
            record(command);
            self.device.end_command_buffer(command).unwrap();
            let fence = self
                .device
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .unwrap();
            let commands = [command];
            self.device
                .queue_submit(
                    self.queue,
                    &[vk::SubmitInfo::default().command_buffers(&commands)],
                    fence,
                )
                .unwrap();
            self.device
                .wait_for_fences(&[fence], true, u64::MAX)
                .unwrap();
            self.device.destroy_fence(fence, None);
            self.device.free_command_buffers(self.pool, &commands);
        }
    }
}

impl Drop for Vulkan {
    fn drop(&mut self) {
        // SAFETY: every child object was destroyed by `Evaluation::drop`.
        unsafe {
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

/// One texture of the table on the device, sampled through a combined image sampler.
struct Texture {
    binding: u32,
    image: vk::Image,
    view: vk::ImageView,
    memory: vk::DeviceMemory,
}

/// Uploads `texture` (f16 texels) as an optimally tiled image in shader-read layout.
fn upload(vulkan: &Vulkan, texture: &TextureData) -> Texture {
    let format = match texture.channels {
        1 => vk::Format::R16_SFLOAT,
        2 => vk::Format::R16G16_SFLOAT,
        4 => vk::Format::R16G16B16A16_SFLOAT,
        n => panic!("{}: {n} channels", texture.name),
    };
    let [width, height, depth] = texture.size;
    let (image_type, extent_depth, layers, view_type) = if texture.three_d {
        (vk::ImageType::TYPE_3D, depth, 1, vk::ImageViewType::TYPE_3D)
    } else {
        (
            vk::ImageType::TYPE_2D,
            1,
            depth,
            vk::ImageViewType::TYPE_2D_ARRAY,
        )
    };
    let extent = vk::Extent3D {
        width,
        height,
        depth: extent_depth,
    };
    let range = vk::ImageSubresourceRange::default()
        .aspect_mask(vk::ImageAspectFlags::COLOR)
        .level_count(1)
        .layer_count(layers);
    let bytes: Vec<u8> = texture
        .texels
        .iter()
        .flat_map(|v| v.to_bits().to_le_bytes())
        .collect();
    let (staging, staging_memory) =
        vulkan.buffer(bytes.len(), vk::BufferUsageFlags::TRANSFER_SRC, &bytes);
    let device = &vulkan.device;
    // SAFETY: see `Vulkan::new`.
    unsafe {
        let image = device
            .create_image(
                &vk::ImageCreateInfo::default()
                    .image_type(image_type)
                    .format(format)
                    .extent(extent)
                    .mip_levels(1)
                    .array_layers(layers)
                    .samples(vk::SampleCountFlags::TYPE_1)
                    .tiling(vk::ImageTiling::OPTIMAL)
                    .usage(vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST),
                None,
            )
            .unwrap();
        let memory = vulkan.allocate(
            device.get_image_memory_requirements(image),
            vk::MemoryPropertyFlags::empty(),
        );
        device.bind_image_memory(image, memory, 0).unwrap();
        vulkan.submit(|command| {
            let barrier = |old, new, src, dst| {
                vk::ImageMemoryBarrier::default()
                    .old_layout(old)
                    .new_layout(new)
                    .src_access_mask(src)
                    .dst_access_mask(dst)
                    .image(image)
                    .subresource_range(range)
            };
            device.cmd_pipeline_barrier(
                command,
                vk::PipelineStageFlags::TOP_OF_PIPE,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[barrier(
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::AccessFlags::empty(),
                    vk::AccessFlags::TRANSFER_WRITE,
                )],
            );
            let region = vk::BufferImageCopy::default()
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(vk::ImageAspectFlags::COLOR)
                        .layer_count(layers),
                )
                .image_extent(extent);
            device.cmd_copy_buffer_to_image(
                command,
                staging,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            );
            device.cmd_pipeline_barrier(
                command,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[barrier(
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    vk::AccessFlags::TRANSFER_WRITE,
                    vk::AccessFlags::SHADER_READ,
                )],
            );
        });
        device.destroy_buffer(staging, None);
        device.free_memory(staging_memory, None);
        let view = device
            .create_image_view(
                &vk::ImageViewCreateInfo::default()
                    .image(image)
                    .view_type(view_type)
                    .format(format)
                    .subresource_range(range),
                None,
            )
            .unwrap();
        Texture {
            binding: texture.binding,
            image,
            view,
            memory,
        }
    }
}

/// F(wi, wo) for each pair by the SPIR-V compute module `spirv` (entry `main`, as GLSL
/// names it) with `table`'s textures.
fn evaluate_glsl(
    vulkan: &Vulkan,
    table: &Table,
    spirv: &[u32],
    pairs: &[(Vec3, Vec3)],
) -> Vec<[f32; 3]> {
    let device = &vulkan.device;
    let textures: Vec<Texture> = table
        .geometry()
        .textures(table.planes())
        .iter()
        .map(|t| upload(vulkan, t))
        .collect();
    let input: Vec<u8> = pairs
        .iter()
        .flat_map(|(wi, wo)| [wi.extend(0.0), wo.extend(0.0)])
        .flat_map(|v| v.to_array())
        .flat_map(f32::to_le_bytes)
        .collect();
    let (pair_buffer, pair_memory) =
        vulkan.buffer(input.len(), vk::BufferUsageFlags::STORAGE_BUFFER, &input);
    let result_bytes = pairs.len() * 16;
    let (result_buffer, result_memory) =
        vulkan.buffer(result_bytes, vk::BufferUsageFlags::STORAGE_BUFFER, &[]);
    // SAFETY: see `Vulkan::new`.
    unsafe {
        // The lookup's sampler: linear, clamp to edge, one mip level (as `GpuTable`'s).
        let sampler = device
            .create_sampler(
                &vk::SamplerCreateInfo::default()
                    .mag_filter(vk::Filter::LINEAR)
                    .min_filter(vk::Filter::LINEAR)
                    .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
                    .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                    .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                    .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE),
                None,
            )
            .unwrap();
        let entry = |binding, kind| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(kind)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        };
        let mut bindings = vec![
            entry(0, vk::DescriptorType::STORAGE_BUFFER),
            entry(1, vk::DescriptorType::STORAGE_BUFFER),
        ];
        bindings.extend(
            textures
                .iter()
                .map(|t| entry(t.binding, vk::DescriptorType::COMBINED_IMAGE_SAMPLER)),
        );
        let set_layout = device
            .create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                None,
            )
            .unwrap();
        let set_layouts = [set_layout];
        let pipeline_layout = device
            .create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts),
                None,
            )
            .unwrap();
        let module = device
            .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(spirv), None)
            .unwrap();
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main");
        let pipeline = device
            .create_compute_pipelines(
                vk::PipelineCache::null(),
                &[vk::ComputePipelineCreateInfo::default()
                    .stage(stage)
                    .layout(pipeline_layout)],
                None,
            )
            .map_err(|(_, e)| e)
            .expect("compute pipeline")[0];
        let sizes = [
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(2),
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(textures.len().max(1) as u32),
        ];
        let descriptor_pool = device
            .create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(&sizes),
                None,
            )
            .unwrap();
        let set = device
            .allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(descriptor_pool)
                    .set_layouts(&set_layouts),
            )
            .unwrap()[0];
        let buffer_infos = [pair_buffer, result_buffer].map(|buffer| {
            [vk::DescriptorBufferInfo::default()
                .buffer(buffer)
                .range(vk::WHOLE_SIZE)]
        });
        let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = textures
            .iter()
            .map(|t| {
                [vk::DescriptorImageInfo::default()
                    .sampler(sampler)
                    .image_view(t.view)
                    .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)]
            })
            .collect();
        let mut writes: Vec<vk::WriteDescriptorSet> = buffer_infos
            .iter()
            .enumerate()
            .map(|(binding, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(binding as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        writes.extend(textures.iter().zip(&image_infos).map(|(t, info)| {
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(t.binding)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .image_info(info)
        }));
        device.update_descriptor_sets(&writes, &[]);
        vulkan.submit(|command| {
            device.cmd_bind_pipeline(command, vk::PipelineBindPoint::COMPUTE, pipeline);
            device.cmd_bind_descriptor_sets(
                command,
                vk::PipelineBindPoint::COMPUTE,
                pipeline_layout,
                0,
                &[set],
                &[],
            );
            device.cmd_dispatch(command, (pairs.len() as u32).div_ceil(WORKGROUP_SIZE), 1, 1);
        });
        let mapped = device
            .map_memory(
                result_memory,
                0,
                result_bytes as u64,
                vk::MemoryMapFlags::empty(),
            )
            .unwrap() as *const u8;
        let bytes = std::slice::from_raw_parts(mapped, result_bytes).to_vec();
        device.unmap_memory(result_memory);

        device.destroy_descriptor_pool(descriptor_pool, None);
        device.destroy_pipeline(pipeline, None);
        device.destroy_shader_module(module, None);
        device.destroy_pipeline_layout(pipeline_layout, None);
        device.destroy_descriptor_set_layout(set_layout, None);
        device.destroy_sampler(sampler, None);
        for (buffer, memory) in [(pair_buffer, pair_memory), (result_buffer, result_memory)] {
            device.destroy_buffer(buffer, None);
            device.free_memory(memory, None);
        }
        for t in textures {
            device.destroy_image_view(t.view, None);
            device.destroy_image(t.image, None);
            device.free_memory(t.memory, None);
        }
        bytes
            .chunks_exact(16)
            .map(|v| {
                std::array::from_fn(|c| f32::from_le_bytes(v[4 * c..4 * c + 4].try_into().unwrap()))
            })
            .collect()
    }
}

#[test]
fn glsl_translation_on_vulkan_agrees_with_wgsl_pair_by_pair() {
    let vulkan = Vulkan::new();
    println!("Vulkan device for the GLSL: {}", vulkan.name);
    let context = gpu_context();
    let dir = temp_dir("glsl-vulkan");
    let mut failures = Vec::new();
    for &layout in Layout::ALL {
        for name in ["polyester_satin_charmeuse", "velvet"] {
            let fabric = fabric(name);
            let table = bake(&fabric, layout, layout.resolution_ladder()[0], &|| {}).unwrap();
            let glsl = dir.join(format!("{}-{name}.comp", layout.name()));
            std::fs::write(&glsl, lookup_shader(&table, ShaderLanguage::Glsl).unwrap()).unwrap();
            let spv = glsl.with_extension("spv");
            let output = Command::new("glslangValidator")
                .args(["-V", path_str(&glsl), "-o", path_str(&spv)])
                .output()
                .expect("glslangValidator (Debian: glslang-tools; scripts/setup.sh installs it)");
            assert!(output.status.success(), "{}", output_text(&output));
            let words: Vec<u32> = std::fs::read(&spv)
                .unwrap()
                .chunks_exact(4)
                .map(|w| u32::from_le_bytes(w.try_into().unwrap()))
                .collect();
            let pairs: Vec<(Vec3, Vec3)> = uniform_pairs(PAIRS, 11)
                .into_iter()
                .chain(highlight_pairs(&fabric, PAIRS, 12))
                .map(|(wi, wo)| (wi.as_vec3(), wo.as_vec3()))
                .collect();
            let from_glsl = evaluate_glsl(&vulkan, &table, &words, &pairs);
            let gpu_table = GpuTable::new(&context, &table).unwrap();
            let from_wgsl = evaluate_pairs(&context, &gpu_table, &pairs).unwrap();
            let largest = from_wgsl.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
            let (mut worst, mut identical, mut lit) = (0.0f64, 0, 0);
            for (a, b) in from_wgsl.iter().zip(&from_glsl) {
                identical += (a == b) as usize;
                lit += b.iter().any(|&v| v > 0.0) as usize;
                for c in 0..3 {
                    if a[c].abs() > 1e-4 * largest {
                        worst = worst.max(((a[c] - b[c]) / a[c]).abs() as f64);
                    }
                }
            }
            println!(
                "{} {name}: GLSL (glslang → SPIR-V, Vulkan) against WGSL (wgpu), {} pairs: \
                 largest relative difference {worst:.2e}, {identical} pairs bit-identical, {lit} \
                 non-zero",
                layout.name(),
                pairs.len()
            );
            // Below the horizon F is 0 on both sides: most pairs must be lit for the
            // comparison to say anything.
            if worst.is_nan() || worst > BOUND || lit < pairs.len() / 2 {
                failures.push(format!("{} {name}: {worst:e}", layout.name()));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
