//! Our departures from the paper, each switchable alone, so that every "ours vs paper"
//! comparison can name what each one buys (the benchmark's ablation table).
//!
//! [`Departures::PAPER`] is the paper's path as published: representative-vector culling
//! (§3.3.2), the linear opacity ramp from boundary to boundary with no time term (§3.3.3),
//! bins neither reference sees culled, the uninflated proxy, and the reference images
//! projected as they are (no depth test, no coverage normalisation). [`Departures::OURS`]
//! switches every departure on.

use crate::bins::{Culling, PlanSettings, Ramp};
use crate::pass::{WarpMode, WarpSettings};
use crate::proxy::Proxy;

/// One departure from the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Departure {
    /// The reference depth test (beyond §3.4): texels hidden in a reference fall back to the
    /// other reference; fragments a reference shows as empty space are dropped. Implies the
    /// coverage-normalised lookup.
    DepthTest,
    /// Reference lookups divided by the reference's coverage (alpha), so silhouette pixels
    /// average only the object's texels instead of projecting the background colour.
    Coverage,
    /// Conservative culling by each bin's normal cone and the object's spread instead of the
    /// representative vector alone (§3.3.2).
    ConservativeCulling,
    /// Bins back-facing in both references but facing the current camera are drawn with the
    /// reference nearer in time instead of culled.
    DrawUnseen,
    /// The proxy inflated by [`Proxy::suggested_inflation`] along its normals.
    Inflation,
    /// The cosine-ratio ramp with a grazing margin instead of the paper's linear ramp
    /// (§3.3.3).
    CosineRamp,
    /// The ramp sharpened to a band of 0.5 around equal weight instead of spanning the whole
    /// overlap.
    BlendBand,
    /// The ramp weighted by time (`1 − s`, `s`), so a warp at a reference pose reproduces it.
    TimeTerm,
}

impl Departure {
    /// Every departure, in table order.
    pub const ALL: [Departure; 8] = [
        Departure::DepthTest,
        Departure::Coverage,
        Departure::ConservativeCulling,
        Departure::DrawUnseen,
        Departure::Inflation,
        Departure::CosineRamp,
        Departure::BlendBand,
        Departure::TimeTerm,
    ];

    /// A short name (table and JSON key value).
    pub fn name(self) -> &'static str {
        match self {
            Departure::DepthTest => "depth-test",
            Departure::Coverage => "coverage",
            Departure::ConservativeCulling => "conservative-culling",
            Departure::DrawUnseen => "draw-unseen-bins",
            Departure::Inflation => "inflation",
            Departure::CosineRamp => "cosine-ramp",
            Departure::BlendBand => "blend-band",
            Departure::TimeTerm => "time-term",
        }
    }
}

/// Which departures are on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Departures {
    /// [`Departure::DepthTest`].
    pub depth_test: bool,
    /// [`Departure::Coverage`].
    pub coverage: bool,
    /// [`Departure::ConservativeCulling`].
    pub conservative_culling: bool,
    /// [`Departure::DrawUnseen`].
    pub draw_unseen: bool,
    /// [`Departure::Inflation`].
    pub inflation: bool,
    /// [`Departure::CosineRamp`].
    pub cosine_ramp: bool,
    /// [`Departure::BlendBand`].
    pub blend_band: bool,
    /// [`Departure::TimeTerm`].
    pub time_term: bool,
}

impl Departures {
    /// The paper's path as published (§3.3.1–§3.3.3).
    pub const PAPER: Departures = Departures {
        depth_test: false,
        coverage: false,
        conservative_culling: false,
        draw_unseen: false,
        inflation: false,
        cosine_ramp: false,
        blend_band: false,
        time_term: false,
    };

    /// Ours: every departure on.
    pub const OURS: Departures = Departures {
        depth_test: true,
        coverage: true,
        conservative_culling: true,
        draw_unseen: true,
        inflation: true,
        cosine_ramp: true,
        blend_band: true,
        time_term: true,
    };

    /// Whether `d` is on.
    pub fn has(&self, d: Departure) -> bool {
        match d {
            Departure::DepthTest => self.depth_test,
            Departure::Coverage => self.coverage,
            Departure::ConservativeCulling => self.conservative_culling,
            Departure::DrawUnseen => self.draw_unseen,
            Departure::Inflation => self.inflation,
            Departure::CosineRamp => self.cosine_ramp,
            Departure::BlendBand => self.blend_band,
            Departure::TimeTerm => self.time_term,
        }
    }

    /// A copy with `d` switched to `on`.
    pub fn with(mut self, d: Departure, on: bool) -> Self {
        let flag = match d {
            Departure::DepthTest => &mut self.depth_test,
            Departure::Coverage => &mut self.coverage,
            Departure::ConservativeCulling => &mut self.conservative_culling,
            Departure::DrawUnseen => &mut self.draw_unseen,
            Departure::Inflation => &mut self.inflation,
            Departure::CosineRamp => &mut self.cosine_ramp,
            Departure::BlendBand => &mut self.blend_band,
            Departure::TimeTerm => &mut self.time_term,
        };
        *flag = on;
        self
    }

    /// `"paper"` or `"ours"` for the two ends, otherwise `None`.
    pub fn label(&self) -> Option<&'static str> {
        if *self == Self::PAPER {
            Some("paper")
        } else if *self == Self::OURS {
            Some("ours")
        } else {
            None
        }
    }

    /// The fragment shader: the depth test (ours), the paper's lookup with coverage
    /// normalisation, or the paper's lookup as published.
    pub fn mode(&self) -> WarpMode {
        if self.depth_test {
            WarpMode::DepthTested
        } else if self.coverage {
            WarpMode::PaperCoverage
        } else {
            WarpMode::Paper
        }
    }

    /// The §3.3.2–§3.3.3 decisions.
    pub fn plan(&self) -> PlanSettings {
        let ours = PlanSettings::default();
        let paper = PlanSettings::paper();
        PlanSettings {
            blend_band: if self.blend_band {
                ours.blend_band
            } else {
                paper.blend_band
            },
            ramp: if self.cosine_ramp {
                Ramp::CosineRatio
            } else {
                Ramp::LinearAngle
            },
            culling: if self.conservative_culling {
                Culling::Conservative
            } else {
                Culling::Representative
            },
            draw_unseen: self.draw_unseen,
            temporal_weight: self.time_term,
            ..ours
        }
    }

    /// The proxy's inflation in object units: [`Proxy::suggested_inflation`] or none.
    pub fn inflation(&self, proxy: &Proxy) -> f32 {
        if self.inflation {
            proxy.suggested_inflation()
        } else {
            0.0
        }
    }

    /// Warp settings for `proxy` drawn with a transform that scales object units by
    /// `world_per_object` ([`WarpSettings::for_proxy`] at this inflation, with this plan).
    pub fn settings(&self, proxy: &Proxy, world_per_object: f32) -> WarpSettings {
        WarpSettings {
            plan: self.plan(),
            ..WarpSettings::for_proxy(proxy, self.inflation(proxy), world_per_object)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ends_are_the_paper_and_ours() {
        assert_eq!(Departures::PAPER.plan(), PlanSettings::paper());
        assert_eq!(Departures::OURS.plan(), PlanSettings::default());
        assert_eq!(Departures::PAPER.mode(), WarpMode::Paper);
        assert_eq!(Departures::OURS.mode(), WarpMode::DepthTested);
        for d in Departure::ALL {
            let one = Departures::PAPER.with(d, true);
            assert!(one.has(d) && one != Departures::PAPER && one.label().is_none());
            assert!(!Departures::OURS.with(d, false).has(d));
        }
    }
}
