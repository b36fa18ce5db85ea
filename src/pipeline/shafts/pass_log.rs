//! The passes of a shafts frame as they finish: each pass's statistics with the
//! memory traffic its units counted, and its recorded work for the clocked chip when
//! the frame records ([`super::frame::ShaftsFrame::record_work`]).

use super::record::Rec;
use crate::chip::work::{PassSample, PassWork, SampleBands};
use crate::chip::{PassKind, PassStats};
use rtl_model::error::ConfigError;
use rtl_model::Counters;
use std::collections::BTreeMap;

/// Where a finished pass's recorded work goes
/// ([`super::frame::ShaftsFrame::record_work`]): called once per pass, in pass order,
/// with the pass's [`PassWork`] (its stats filled in). It owns what it keeps (share it
/// with `Rc<RefCell<…>>` to read it back).
pub type WorkSink = Box<dyn FnMut(PassWork) -> Result<(), ConfigError>>;

/// Cumulative traffic over every unit's counters so far (to split it per pass).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Traffic {
    texel_bytes: u64,
    fb_bytes: u64,
    depth_tests: u64,
}

/// The traffic in the counters so far: texel bytes (the samplers' reads, 4 bytes per
/// shadow-map lookup), framebuffer bytes (the additive blends' reads and writes) and
/// camera depth tests.
fn traffic(ctr: &BTreeMap<String, Counters>) -> Traffic {
    let mut t = Traffic::default();
    for (k, c) in ctr {
        if k.starts_with("texture_sampler") {
            t.texel_bytes += c.mem_read_bytes;
        } else if k.starts_with("additive_blend") {
            t.fb_bytes += c.mem_read_bytes + c.mem_write_bytes;
        } else if k == "shadow_compare (depth buffer)" {
            t.depth_tests += c.pixels_in;
        } else if k == "shadow_compare (shadow map)" {
            // Shadow-map lookups are depth-texture fetches: one 32-bit texel each.
            t.texel_bytes += 4 * c.pixels_in;
        }
    }
    t
}

/// The passes of a frame so far: their statistics, the traffic counted up to the last
/// one, and where their recorded work goes when it is asked for.
pub(super) struct PassLog {
    pub passes: Vec<PassStats>,
    last: Traffic,
    sink: Option<WorkSink>,
    /// When recording: the sampled bands whose fragments alone are recorded (`None`:
    /// every fragment).
    pub bands: Option<SampleBands>,
    /// When recording: which passes of each kind are recorded (the others send their
    /// stats alone).
    pub pass_sample: PassSample,
}

impl PassLog {
    /// No pass yet, recording nothing.
    pub fn new() -> Self {
        PassLog {
            passes: Vec::new(),
            last: Traffic::default(),
            sink: None,
            bands: None,
            pass_sample: PassSample::ALL,
        }
    }

    /// Record each pass's work from now on into `sink`.
    pub fn record(&mut self, sink: WorkSink) {
        self.sink = Some(sink);
    }

    /// Whether the passes record their work.
    pub fn recording(&self) -> bool {
        self.sink.is_some()
    }

    /// What pass `n` of its kind (numbered from 0 in draw order) records
    /// ([`PassSample`]): `None` nothing, else the bands whose fragments it keeps
    /// (`None`: every fragment). A copy of the log's choice that does not borrow it,
    /// for passes computed ahead and in parallel (the sub-planes).
    pub fn recorder(&self) -> impl Fn(usize) -> Option<Option<SampleBands>> + Sync + Copy {
        let (recording, sample, bands) = (self.recording(), self.pass_sample, self.bands);
        move |n| (recording && sample.records(n)).then_some(bands)
    }

    /// Whether pass `n` of its kind records its work ([`PassLog::recorder`]).
    pub fn records(&self, n: usize) -> bool {
        self.recorder()(n).is_some()
    }

    /// A fresh record when recording (of the sampled bands' fragments in sampled mode)
    /// for the first pass of its kind.
    pub fn new_rec(&self) -> Option<Rec> {
        self.records(0).then(|| Rec::sampled(self.bands))
    }

    /// Push a finished pass, attributing the traffic counted since the previous one;
    /// when recording, its work (`work`, the stats filled in) goes to the sink, or,
    /// for a pass the sampled mode does not record (`None`), its stats alone, marked
    /// unrecorded.
    pub fn push(
        &mut self,
        ctr: &BTreeMap<String, Counters>,
        mut st: PassStats,
        work: Option<PassWork>,
    ) -> Result<(), ConfigError> {
        let now = traffic(ctr);
        st.texel_bytes = now.texel_bytes - self.last.texel_bytes;
        st.fb_bytes = now.fb_bytes - self.last.fb_bytes;
        st.depth_tests = now.depth_tests - self.last.depth_tests;
        self.last = now;
        if let Some(sink) = self.sink.as_mut() {
            let mut w = work.unwrap_or(PassWork {
                unrecorded: true,
                ..PassWork::default()
            });
            w.stats = Some(st.clone());
            sink(w)?;
        }
        self.passes.push(st);
        Ok(())
    }
}

impl PassStats {
    pub(super) fn new(kind: PassKind, light: usize, textures_per_fragment: u32) -> Self {
        PassStats {
            kind,
            light,
            walked: 0,
            fragments: 0,
            textures_per_fragment,
            triangles: 0,
            texel_bytes: 0,
            fb_bytes: 0,
            other_bytes: 0,
            depth_tests: 0,
        }
    }
}
