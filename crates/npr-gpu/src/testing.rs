//! A process-wide GPU context for tests, and the rule for what a test does without one.
//!
//! A GPU test that finds no adapter FAILS, with the hint to run `cargo xtask doctor`
//! (which finds or installs a driver). It is skipped only when the user asks for that
//! explicitly with `NPR_SKIP_GPU=1`; each skip then writes
//! `npr: N GPU tests skipped (NPR_SKIP_GPU=1) ...` straight to the process's stderr handle,
//! which libtest's output capture does not intercept (it captures only the `print!`
//! family), so the count shows under plain `cargo test`. The last such line of a test
//! binary holds its total. `NPR_REQUIRE_GPU=1` (set by `cargo xtask test`) overrides
//! `NPR_SKIP_GPU`: there a missing adapter always fails. The rule itself is the pure
//! function [`no_adapter_action`].

use crate::GpuContext;
use std::io::Write as _;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Environment variable that makes a missing adapter a test failure even when
/// [`SKIP_GPU_ENV`] is set (`cargo xtask test` sets it after making sure of a driver).
pub const REQUIRE_GPU_ENV: &str = "NPR_REQUIRE_GPU";

/// Environment variable that, set to `1`, turns a missing adapter into a counted skip.
pub const SKIP_GPU_ENV: &str = "NPR_SKIP_GPU";

/// The hint a failing GPU test prints.
pub const DOCTOR_HINT: &str = "run `cargo xtask doctor` to find or install a GPU driver \
     (Mesa lavapipe on Debian/Ubuntu), or set NPR_SKIP_GPU=1 to skip GPU tests";

/// What a GPU test does when no adapter exists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoAdapter {
    /// Fail (panic) with [`DOCTOR_HINT`]: the default.
    Fail,
    /// Return early and count the skip: only with `NPR_SKIP_GPU=1` and without
    /// `NPR_REQUIRE_GPU=1`.
    Skip,
}

/// The rule, from the values of [`SKIP_GPU_ENV`] and [`REQUIRE_GPU_ENV`] (`None` when
/// unset): skip only when `NPR_SKIP_GPU` is exactly `1` and `NPR_REQUIRE_GPU` is not `1`.
pub fn no_adapter_action(skip_gpu: Option<&str>, require_gpu: Option<&str>) -> NoAdapter {
    if require_gpu != Some("1") && skip_gpu == Some("1") {
        NoAdapter::Skip
    } else {
        NoAdapter::Fail
    }
}

/// The line a skip writes to stderr, `count` being the skips so far in this binary.
pub fn skip_line(count: usize, test: &str) -> String {
    let tests = if count == 1 { "test" } else { "tests" };
    format!(
        "npr: {count} GPU {tests} skipped ({SKIP_GPU_ENV}=1) so far in this test binary; last: {test}"
    )
}

static CONTEXT: OnceLock<Result<GpuContext, String>> = OnceLock::new();
static SKIPPED: AtomicUsize = AtomicUsize::new(0);

/// The shared context, created on first use (one device per test process).
///
/// # Errors
/// The message of the [`crate::GpuError`] that creating it returned.
pub fn shared_context() -> Result<&'static GpuContext, &'static str> {
    CONTEXT
        .get_or_init(|| {
            let ctx = GpuContext::new().map_err(|e| e.to_string())?;
            eprintln!("npr-gpu tests: adapter {}", ctx.adapter_summary());
            Ok(ctx)
        })
        .as_ref()
        .map_err(String::as_str)
}

/// The shared context for a GPU test, or `None` when the test is skipped (only with
/// `NPR_SKIP_GPU=1`; see the module docs).
///
/// # Panics
/// When no adapter exists and [`no_adapter_action`] says [`NoAdapter::Fail`] (the
/// default): the message carries the adapter error and [`DOCTOR_HINT`].
pub fn context_or_skip(test: &str) -> Option<&'static GpuContext> {
    match shared_context() {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            let skip = std::env::var(SKIP_GPU_ENV).ok();
            let require = std::env::var(REQUIRE_GPU_ENV).ok();
            match no_adapter_action(skip.as_deref(), require.as_deref()) {
                NoAdapter::Fail => panic!("{test}: no GPU adapter ({e}); {DOCTOR_HINT}"),
                NoAdapter::Skip => {
                    let count = SKIPPED.fetch_add(1, Ordering::SeqCst) + 1;
                    // The raw handle, not eprintln!: libtest captures the macros only.
                    let _ = writeln!(std::io::stderr().lock(), "{}", skip_line(count, test));
                    None
                }
            }
        }
    }
}

/// How many GPU tests of this binary have been skipped so far.
pub fn skipped_count() -> usize {
    SKIPPED.load(Ordering::SeqCst)
}

/// Where failing image comparisons leave their pictures: `target/test-images/`, found from
/// the test executable's own path (`target/<profile>/deps/<test>`), so it holds under any
/// `CARGO_TARGET_DIR`.
pub fn test_images_dir() -> std::path::PathBuf {
    let exe = std::env::current_exe().unwrap_or_default();
    // <target>/<profile>/deps/<exe>, or <target>/<profile>/examples/<exe>.
    let target = exe
        .ancestors()
        .nth(3)
        .map(std::path::Path::to_path_buf)
        .unwrap_or_else(std::env::temp_dir);
    target.join("test-images")
}

/// Writes the pictures of a failed image comparison, as wgpu's image tests do:
/// `NAME-expected.png`, `NAME-actual.png` and `NAME-difference.png` (`|a − b|` per RGB
/// channel, ×4, opaque) under [`test_images_dir`]. Returns one line naming the three paths,
/// to end the failing assertion's message with; a write error is named in the line instead.
///
/// Call it in the message of an assertion (`assert!(ok, "...; {}", image_failure(..))`):
/// the arguments are evaluated only when the assertion fails.
pub fn image_failure(name: &str, expected: &image::RgbaImage, actual: &image::RgbaImage) -> String {
    let dir = test_images_dir();
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let path = |kind: &str| dir.join(format!("{safe}-{kind}.png"));
    let difference = difference(expected, actual);
    let written = std::fs::create_dir_all(&dir)
        .map_err(|e| e.to_string())
        .and_then(|()| {
            for (kind, img) in [
                ("expected", expected),
                ("actual", actual),
                ("difference", &difference),
            ] {
                img.save(path(kind)).map_err(|e| e.to_string())?;
            }
            Ok(())
        });
    match written {
        Ok(()) => format!(
            "images: {} {} {}",
            path("expected").display(),
            path("actual").display(),
            path("difference").display()
        ),
        Err(e) => format!(
            "the failure images could not be written under {}: {e}",
            dir.display()
        ),
    }
}

/// `4 × |a − b|` per RGB channel over the overlap of the two images, opaque.
fn difference(a: &image::RgbaImage, b: &image::RgbaImage) -> image::RgbaImage {
    let (w, h) = (a.width().min(b.width()), a.height().min(b.height()));
    image::RgbaImage::from_fn(w, h, |x, y| {
        let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
        let c = |i: usize| p[i].abs_diff(q[i]).saturating_mul(4);
        image::Rgba([c(0), c(1), c(2), 255])
    })
}

#[cfg(test)]
mod failure_image_tests {
    use super::*;

    #[test]
    fn a_failure_writes_the_three_pictures_and_names_them() {
        let a = image::RgbaImage::from_pixel(8, 4, image::Rgba([10, 20, 30, 255]));
        let mut b = a.clone();
        b.put_pixel(3, 2, image::Rgba([50, 20, 30, 255]));
        let line = image_failure("npr-gpu self test/one pixel", &a, &b);
        let dir = test_images_dir();
        for kind in ["expected", "actual", "difference"] {
            let p = dir.join(format!("npr-gpu_self_test_one_pixel-{kind}.png"));
            assert!(line.contains(&p.display().to_string()), "{line}");
            assert!(p.is_file(), "{} missing", p.display());
        }
        let diff = image::open(dir.join("npr-gpu_self_test_one_pixel-difference.png"))
            .map(|i| i.to_rgba8());
        let diff = diff.unwrap_or_default();
        assert_eq!(diff.get_pixel(3, 2).0, [160, 0, 0, 255]);
        assert_eq!(diff.get_pixel(0, 0).0, [0, 0, 0, 255]);
        assert!(dir.ends_with("target/test-images") || dir.ends_with("test-images"));
    }
}

/// WGSL validation and struct layouts read with naga's reflection, for tests that compare
/// them with the `#[repr(C)]` Rust structs that fill the buffers.
///
/// A technique crate enables it for its tests only:
/// `[dev-dependencies] npr-gpu = { workspace = true, features = ["test-support"] }`, then
/// in a unit test next to its (private) uniform struct, naming its own shader list:
///
/// ```text
/// npr_gpu::assert_wgsl_layout!(crate::shaders::ALL, WarpObjectUniforms, "WarpObject", [world_from_object, ...]);
/// ```
pub mod wgsl_layout {
    use crate::shaders::ShaderFile;
    use std::path::Path;

    /// One member of a WGSL struct: name, byte offset, byte size.
    #[derive(Clone, Debug, PartialEq, Eq)]
    pub struct Member {
        /// Member name.
        pub name: String,
        /// Byte offset in the struct (naga's `StructMember::offset`).
        pub offset: u32,
        /// Byte size of the member's type (naga's `Layouter`).
        pub size: u32,
    }

    /// A `var<uniform>` (or `var<storage>`) of a shader whose type is a struct.
    #[derive(Clone, Debug, PartialEq, Eq)]
    pub struct Block {
        /// Shader file name (the [`ShaderFile::name`] of an entry of the list searched).
        pub shader: &'static str,
        /// Variable name.
        pub variable: String,
        /// Whether it is in the uniform address space (else storage).
        pub uniform: bool,
        /// Name of the struct type (for an array of structs, the element's struct).
        pub struct_name: String,
        /// Size of the struct in bytes (the struct's `span`).
        pub size: u32,
        /// Its members in declaration order.
        pub members: Vec<Member>,
    }

    /// Every struct-typed uniform and storage variable (storage arrays of structs count
    /// by their element) of every composed shader in `shaders`, as naga lays them out.
    ///
    /// # Errors
    /// A parse or layout error, naming the shader.
    pub fn blocks(shaders: &[ShaderFile]) -> Result<Vec<Block>, String> {
        let mut out = Vec::new();
        for entry in shaders {
            let source = entry.full_source();
            let module = naga::front::wgsl::parse_str(&source)
                .map_err(|e| format!("{}: {}", entry.name, e.emit_to_string(&source)))?;
            let mut layouter = naga::proc::Layouter::default();
            layouter
                .update(module.to_ctx())
                .map_err(|e| format!("{}: layout: {e}", entry.name))?;
            for (_, var) in module.global_variables.iter() {
                let uniform = match var.space {
                    naga::AddressSpace::Uniform => true,
                    naga::AddressSpace::Storage { .. } => false,
                    _ => continue,
                };
                let mut ty = var.ty;
                if let naga::TypeInner::Array { base, .. } = module.types[ty].inner {
                    ty = base;
                }
                let naga::TypeInner::Struct { members, span } = &module.types[ty].inner else {
                    continue;
                };
                out.push(Block {
                    shader: entry.name,
                    variable: var.name.clone().unwrap_or_default(),
                    uniform,
                    struct_name: module.types[ty].name.clone().unwrap_or_default(),
                    size: *span,
                    members: members
                        .iter()
                        .map(|m| Member {
                            name: m.name.clone().unwrap_or_default(),
                            offset: m.offset,
                            size: layouter[m.ty].size,
                        })
                        .collect(),
                })
            }
        }
        Ok(out)
    }

    /// Compares WGSL struct `wgsl_struct`, in every shader of `shaders` that binds it,
    /// with a Rust struct of `rust_size` bytes whose fields, in order, are `rust_fields`
    /// (`(WGSL member name, offset_of!)`). Returns how many blocks were compared.
    ///
    /// # Errors
    /// Every difference (size, member names, offsets, a member running past the next),
    /// or no shader binding the struct at all.
    pub fn check(
        shaders: &[ShaderFile],
        wgsl_struct: &str,
        rust_size: usize,
        rust_fields: &[(&str, usize)],
    ) -> Result<usize, String> {
        let mut problems = Vec::new();
        let mut checked = 0;
        for b in blocks(shaders)?
            .iter()
            .filter(|b| b.struct_name == wgsl_struct)
        {
            checked += 1;
            let at = format!("{wgsl_struct} ({} in {})", b.variable, b.shader);
            if b.size as usize != rust_size {
                problems.push(format!(
                    "{at}: WGSL size {} != Rust size {rust_size}",
                    b.size
                ));
            }
            let wgsl: Vec<&str> = b.members.iter().map(|m| m.name.as_str()).collect();
            let rust: Vec<&str> = rust_fields.iter().map(|f| f.0).collect();
            if wgsl != rust {
                problems.push(format!(
                    "{at}: WGSL members {wgsl:?} != Rust fields {rust:?}"
                ));
                continue;
            }
            for (m, (_, offset)) in b.members.iter().zip(rust_fields) {
                if m.offset as usize != *offset {
                    problems.push(format!(
                        "{at}.{}: WGSL offset {} != Rust offset {offset}",
                        m.name, m.offset
                    ));
                }
            }
            for pair in b.members.windows(2) {
                if pair[0].offset + pair[0].size > pair[1].offset {
                    problems.push(format!("{at}.{}: overlaps the next member", pair[0].name));
                }
            }
        }
        if checked == 0 {
            problems.push(format!("no shader binds a struct named {wgsl_struct}"));
        }
        if problems.is_empty() {
            Ok(checked)
        } else {
            Err(problems.join("\n"))
        }
    }

    /// Checks that `shaders` names exactly the `.wgsl` files of directory `dir` (a crate's
    /// `shaders/`) and that every composed shader parses and validates with naga. Returns
    /// how many shaders validated.
    ///
    /// # Errors
    /// Every problem at once: a file not listed, an entry without its file, a parse or
    /// validation error (with naga's report), or an unreadable or empty directory.
    pub fn validate_dir(dir: &Path, shaders: &[ShaderFile]) -> Result<usize, String> {
        let mut failures = Vec::new();
        let mut on_disk: Vec<String> = std::fs::read_dir(dir)
            .map_err(|e| format!("cannot read {}: {e}", dir.display()))?
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".wgsl"))
            .collect();
        on_disk.sort();
        if on_disk.is_empty() {
            return Err(format!("no shader files found in {}", dir.display()));
        }
        for name in &on_disk {
            if !shaders.iter().any(|e| e.name == name) {
                failures.push(format!("{name}: not listed in the crate's shaders::ALL"));
            }
        }
        for entry in shaders {
            let name = entry.name;
            if !on_disk.iter().any(|f| f == name) {
                failures.push(format!(
                    "{name}: listed in shaders::ALL but not in {}",
                    dir.display()
                ));
            }
            let source = entry.full_source();
            let module = match naga::front::wgsl::parse_str(&source) {
                Ok(m) => m,
                Err(e) => {
                    failures.push(format!(
                        "{name}: parse error:\n{}",
                        e.emit_to_string(&source)
                    ));
                    continue;
                }
            };
            let mut validator = naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::default(),
            );
            match validator.validate(&module) {
                Err(e) => failures.push(format!(
                    "{name}: validation error:\n{}",
                    e.emit_to_string(&source)
                )),
                Ok(info) => failures.extend(workgroup_memory_over(&module, &info, name)),
            }
            for function in module
                .functions
                .iter()
                .map(|(_, f)| f)
                .chain(module.entry_points.iter().map(|e| &e.function))
            {
                if function.result.is_some() && can_fall_off(&function.body) {
                    failures.push(format!(
                        "{name}: fn {} can reach its end without a return (e.g. ends in \
                         `discard`): naga accepts it, browsers' WGSL compilers reject it \
                         (\"missing return at end of function\")",
                        function.name.as_deref().unwrap_or("?")
                    ));
                }
            }
        }
        if failures.is_empty() {
            Ok(shaders.len())
        } else {
            Err(format!(
                "{} shader problem(s):\n{}",
                failures.len(),
                failures.join("\n\n")
            ))
        }
    }

    /// WebGPU's default `maxComputeWorkgroupStorageSize`, which browsers enforce when a
    /// pipeline is made (a native adapter may allow more and accept the shader).
    const WORKGROUP_STORAGE_LIMIT: u32 = 16_384;

    /// The entry points of `module` whose workgroup variables take more than
    /// [`WORKGROUP_STORAGE_LIMIT`] bytes.
    fn workgroup_memory_over(
        module: &naga::Module,
        info: &naga::valid::ModuleInfo,
        name: &str,
    ) -> Vec<String> {
        let ctx = module.to_ctx();
        module
            .entry_points
            .iter()
            .enumerate()
            .filter_map(|(i, entry)| {
                let used = info.get_entry_point(i);
                let bytes: u32 = module
                    .global_variables
                    .iter()
                    .filter(|(h, v)| {
                        v.space == naga::AddressSpace::WorkGroup && !used[*h].is_empty()
                    })
                    .map(|(_, v)| module.types[v.ty].inner.size(ctx))
                    .sum();
                (bytes > WORKGROUP_STORAGE_LIMIT).then(|| {
                    format!(
                        "{name}: {} uses {bytes} bytes of workgroup memory, over WebGPU's \
                         {WORKGROUP_STORAGE_LIMIT} (browsers refuse the pipeline)",
                        entry.name
                    )
                })
            })
            .collect()
    }

    /// Whether control can reach the end of `block` without a `return`, by WGSL's behaviour
    /// analysis: `discard` falls through (it only demotes the invocation), a loop does not
    /// (it leaves only by `break` or `return`, conservatively), an `if` or `switch` falls
    /// through when one of its branches does. naga ends a function's body with an
    /// implicit value-less `return`, which counts as falling off for a function with a
    /// result.
    fn can_fall_off(block: &naga::Block) -> bool {
        use naga::Statement as S;
        match block.last() {
            None => true,
            Some(S::Return { value }) => value.is_none(),
            Some(S::Kill) => true,
            Some(S::Block(b)) => can_fall_off(b),
            Some(S::If { accept, reject, .. }) => can_fall_off(accept) || can_fall_off(reject),
            Some(S::Switch { cases, .. }) => cases
                .iter()
                .any(|c| !c.fall_through && can_fall_off(&c.body)),
            Some(S::Loop { .. } | S::Break | S::Continue) => false,
            Some(_) => true,
        }
    }

    /// Checks npr-gpu's shared `Frame` and `Object` blocks (`COMMON`), in every shader of
    /// `shaders` that binds them, against [`crate::FrameUniforms`] and
    /// [`crate::ObjectUniforms`]; returns how many `Frame` and `Object` blocks it compared.
    ///
    /// # Panics
    /// On the first mismatch, naming the struct and the shader.
    pub fn shared_blocks(shaders: &[ShaderFile]) -> (usize, usize) {
        use crate::{FrameUniforms, ObjectUniforms};
        let frames = crate::assert_wgsl_layout!(
            shaders,
            FrameUniforms,
            "Frame",
            [
                clip_from_world,
                eye_world,
                light_world,
                light_color,
                ambient
            ]
        );
        let objects = crate::assert_wgsl_layout!(
            shaders,
            ObjectUniforms,
            "Object",
            [world_from_object, normal_from_object, diffuse, specular]
        );
        (frames, objects)
    }

    /// Checks that every struct bound as `var<uniform>` or `var<storage>` in `shaders` is
    /// named in `covered` (the structs whose Rust twins have an [`assert_wgsl_layout!`]
    /// test), and that every name in `covered` is still bound somewhere. Returns the number
    /// of uniform blocks.
    ///
    /// [`assert_wgsl_layout!`]: crate::assert_wgsl_layout
    ///
    /// # Errors
    /// The structs without a layout test, or the covered names no shader binds.
    pub fn check_coverage(shaders: &[ShaderFile], covered: &[&str]) -> Result<usize, String> {
        let blocks = blocks(shaders)?;
        let mut problems: Vec<String> = blocks
            .iter()
            .filter(|b| !covered.contains(&b.struct_name.as_str()))
            .map(|b| {
                format!(
                    "bound struct without a layout test: {} ({} in {})",
                    b.struct_name, b.variable, b.shader
                )
            })
            .collect();
        problems.dedup();
        for name in covered {
            if !blocks.iter().any(|b| b.struct_name == *name) {
                problems.push(format!("{name} is no longer bound by any shader"));
            }
        }
        if problems.is_empty() {
            Ok(blocks.iter().filter(|b| b.uniform).count())
        } else {
            Err(problems.join("\n"))
        }
    }
}

/// Asserts that Rust struct `$ty` has the layout of WGSL struct `$wgsl` in every shader
/// of the list `$shaders` (`&[ShaderFile]`, composed) that binds it: same size, the listed
/// fields are the WGSL members in order (same names) at the same offsets. Needs the
/// `test-support` feature of `npr-gpu` (a test-only helper).
///
/// ```text
/// npr_gpu::assert_wgsl_layout!(npr_gpu::shaders::ALL, FrameUniforms, "Frame", [clip_from_world, eye_world]);
/// ```
#[macro_export]
macro_rules! assert_wgsl_layout {
    ($shaders:expr, $ty:ty, $wgsl:expr, [$($field:ident),* $(,)?]) => {
        match $crate::testing::wgsl_layout::check(
            $shaders,
            $wgsl,
            ::std::mem::size_of::<$ty>(),
            &[$((stringify!($field), ::std::mem::offset_of!($ty, $field))),*],
        ) {
            Ok(blocks) => blocks,
            Err(e) => panic!("{} does not match WGSL {}:\n{e}", stringify!($ty), $wgsl),
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_adapter_fails_unless_skipping_is_asked_for() {
        assert_eq!(no_adapter_action(None, None), NoAdapter::Fail);
        assert_eq!(no_adapter_action(Some("0"), None), NoAdapter::Fail);
        assert_eq!(no_adapter_action(Some("yes"), None), NoAdapter::Fail);
        assert_eq!(no_adapter_action(Some(""), None), NoAdapter::Fail);
        assert_eq!(no_adapter_action(Some("1"), None), NoAdapter::Skip);
        assert_eq!(no_adapter_action(Some("1"), Some("0")), NoAdapter::Skip);
        // `cargo xtask test` requires the GPU: its NPR_REQUIRE_GPU=1 wins.
        assert_eq!(no_adapter_action(Some("1"), Some("1")), NoAdapter::Fail);
        assert_eq!(no_adapter_action(None, Some("1")), NoAdapter::Fail);
    }

    /// Every struct bound as `var<uniform>` or `var<storage>` in this crate's shaders has
    /// a layout test (the technique crates check theirs the same way).
    #[test]
    fn every_bound_struct_has_a_layout_test() {
        // Frame, Object: uniforms::tests::layouts_match_wgsl; OutlineCamera, OutlineParams:
        // outline::tests::uniform_layouts_match_wgsl; CurvatureParams:
        // curvature::tests::params_layout_matches_wgsl.
        let covered = [
            "Frame",
            "Object",
            "OutlineCamera",
            "OutlineParams",
            "CurvatureParams",
        ];
        let uniforms = wgsl_layout::check_coverage(crate::shaders::ALL, &covered).unwrap();
        assert!(uniforms >= 4, "{uniforms} uniform blocks");
    }

    #[test]
    fn a_wrong_layout_is_reported() {
        // Same size, members swapped: must fail, naming the offsets.
        let e = wgsl_layout::check(
            crate::shaders::ALL,
            "Frame",
            128,
            &[("clip_from_world", 0), ("eye_world", 80)],
        )
        .unwrap_err();
        assert!(e.contains("members"), "{e}");
        let fields = [
            ("clip_from_world", 0),
            ("eye_world", 64),
            ("light_world", 96),
            ("light_color", 80),
            ("ambient", 112),
        ];
        let e = wgsl_layout::check(crate::shaders::ALL, "Frame", 128, &fields).unwrap_err();
        assert!(
            e.contains("light_world: WGSL offset 80 != Rust offset 96"),
            "{e}"
        );
        assert!(wgsl_layout::check(crate::shaders::ALL, "NoSuchStruct", 16, &[]).is_err());
    }

    #[test]
    fn the_skip_line_carries_the_count() {
        assert_eq!(
            skip_line(3, "t"),
            "npr: 3 GPU tests skipped (NPR_SKIP_GPU=1) so far in this test binary; last: t"
        );
        assert!(skip_line(1, "t").starts_with("npr: 1 GPU test skipped"));
    }
}

/// A readback copy of `buffer`, recorded into `encoder` (read it after the submit with
/// [`read_mapped`]): how the compute tests read a pass's output.
pub fn copy_for_readback(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    buffer: &wgpu::Buffer,
) -> wgpu::Buffer {
    let size = buffer.size();
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("npr test readback"),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_buffer_to_buffer(buffer, 0, &read, 0, size);
    read
}

/// The bytes of a [`copy_for_readback`] buffer, once its submission is done (waits).
///
/// # Panics
/// When mapping fails (a test helper).
#[allow(clippy::expect_used)]
pub fn read_mapped(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Vec<u8> {
    buffer
        .slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.expect("map"));
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    buffer.get_mapped_range(..).expect("mapped range").to_vec()
}

/// Mean LDR FLIP of `test` against `reference` (same size) over the object's pixels
/// (alpha above 0 in either; transparent pixels count as black), at
/// `nv_flip::DEFAULT_PIXELS_PER_DEGREE` (67: a 31.6-inch 3840-pixel-wide monitor seen
/// from 0.7 m). 0 for identical images; `None` for mismatched sizes or no object pixels.
pub fn flip_mean(reference: &image::RgbaImage, test: &image::RgbaImage) -> Option<f64> {
    flip_stats(reference, test).map(|(mean, _)| mean)
}

/// Mean and largest per-pixel LDR FLIP over the object's pixels (see [`flip_mean`]).
pub fn flip_stats(reference: &image::RgbaImage, test: &image::RgbaImage) -> Option<(f64, f64)> {
    if reference.dimensions() != test.dimensions() {
        return None;
    }
    let (w, h) = reference.dimensions();
    let rgb = |img: &image::RgbaImage| -> Vec<u8> {
        img.pixels()
            .flat_map(|p| if p[3] > 0 { [p[0], p[1], p[2]] } else { [0; 3] })
            .collect()
    };
    let (a, b) = (reference.as_raw(), test.as_raw());
    let mask: Vec<bool> = (0..(w * h) as usize)
        .map(|i| a[4 * i + 3] > 0 || b[4 * i + 3] > 0)
        .collect();
    let pixels = mask.iter().filter(|m| **m).count();
    if pixels == 0 || w == 0 || h == 0 {
        return None;
    }
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(reference)),
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(test)),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    )
    .to_vec();
    let (mut sum, mut max) = (0.0f64, 0.0f64);
    for (e, _) in error.iter().zip(&mask).filter(|(_, m)| **m) {
        sum += f64::from(*e);
        max = max.max(f64::from(*e));
    }
    Some((sum / pixels as f64, max))
}
