//! `npr-web-check`: the browser check's build of the page. It is `npr-web` (whose exports
//! it carries: the page runs as published) plus [`ComputeCheck`], which runs the compute
//! passes on the page's own WebGPU device and compares them with the CPU in the page
//! (`compute_check`, `compute_frame`). Only `cargo xtask web --check` builds it; the
//! published page (`cargo xtask web --build-only`) has none of it. On native targets the
//! crate is empty.

#[cfg(target_arch = "wasm32")]
mod compute_check;
#[cfg(target_arch = "wasm32")]
mod compute_frame;

#[cfg(target_arch = "wasm32")]
pub use check::ComputeCheck;

#[cfg(target_arch = "wasm32")]
mod check {
    use npr_web::Viewer;
    use wasm_bindgen::prelude::*;

    /// The compute check on its way: started on a viewer's device, read back over the
    /// next animation frames.
    #[wasm_bindgen]
    pub struct ComputeCheck {
        running: Option<crate::compute_check::ComputeCheck>,
    }

    #[wasm_bindgen]
    impl ComputeCheck {
        /// Starts the check on `viewer`'s device: the curvature, `N = H`, region and
        /// receiver passes on a torus and frames made wholly on the GPU on a knot.
        pub fn start(viewer: &Viewer) -> Result<ComputeCheck, JsValue> {
            let (device, queue) = viewer.gpu();
            let running = crate::compute_check::ComputeCheck::start(device, queue)
                .map_err(|e| JsValue::from_str(&e))?;
            Ok(Self {
                running: Some(running),
            })
        }

        /// The report as JSON once its readbacks have completed (call it from later
        /// animation frames); an empty string before, and after the report was given.
        pub fn result(&mut self, viewer: &Viewer) -> Result<String, JsValue> {
            let Some(check) = self.running.as_mut() else {
                return Ok(String::new());
            };
            let (device, queue) = viewer.gpu();
            match check
                .poll(device, queue)
                .map_err(|e| JsValue::from_str(&e))?
            {
                Some(report) => {
                    self.running = None;
                    Ok(report.to_string())
                }
                None => Ok(String::new()),
            }
        }
    }
}
