//! VCD traces from the tick driver (GTKWave reads them).

use crate::unit::Signal;
use std::collections::HashMap;
use std::io::{self, Write};
use vcd::{IdCode, TimescaleUnit, Value};

/// A VCD writer for one unit: clock, accept/stall, stage valid bits, and the named
/// fields of the input and output words. One clock = 10 time units (10 ns at 100 MHz
/// nominal; the timescale is symbolic, cycles are what count).
pub struct VcdTrace<W: Write> {
    w: vcd::Writer<W>,
    clk: IdCode,
    accept: IdCode,
    stall: IdCode,
    out_valid: IdCode,
    stages: IdCode,
    latency: u32,
    ins: HashMap<&'static str, (IdCode, u32)>,
    outs: HashMap<&'static str, (IdCode, u32)>,
}

impl<W: Write> VcdTrace<W> {
    /// Declare the signals: `in_fields`/`out_fields` give each field's name and width.
    pub fn new(
        writer: W,
        unit_name: &str,
        latency: u32,
        in_fields: &[Signal],
        out_fields: &[Signal],
    ) -> io::Result<Self> {
        let mut w = vcd::Writer::new(writer);
        w.timescale(1, TimescaleUnit::NS)?;
        w.add_module(unit_name)?;
        let clk = w.add_wire(1, "clk")?;
        let accept = w.add_wire(1, "in_accept")?;
        let stall = w.add_wire(1, "in_stall")?;
        let stages = w.add_wire(latency.max(1), "stage_valid")?;
        let out_valid = w.add_wire(1, "out_valid")?;
        let mut ins = HashMap::new();
        for s in in_fields {
            let id = w.add_wire(s.width, &format!("in_{}", s.name))?;
            ins.insert(s.name, (id, s.width));
        }
        let mut outs = HashMap::new();
        for s in out_fields {
            let id = w.add_wire(s.width, &format!("out_{}", s.name))?;
            outs.insert(s.name, (id, s.width));
        }
        w.upscope()?;
        w.enddefinitions()?;
        Ok(VcdTrace {
            w,
            clk,
            accept,
            stall,
            out_valid,
            stages,
            latency: latency.max(1),
            ins,
            outs,
        })
    }

    /// Record one clock: rising edge at 10·cycle, falling edge at 10·cycle + 5.
    #[allow(clippy::too_many_arguments)]
    pub fn clock(
        &mut self,
        cycle: u64,
        accept: bool,
        stall: bool,
        in_sig: &[Signal],
        stage_valid: &[bool],
        out_valid: bool,
        out_sig: &[Signal],
    ) -> io::Result<()> {
        self.w.timestamp(cycle * 10)?;
        self.w.change_scalar(self.clk, Value::V1)?;
        self.w.change_scalar(self.accept, bit(accept))?;
        self.w.change_scalar(self.stall, bit(stall))?;
        self.w.change_scalar(self.out_valid, bit(out_valid))?;
        let bits: Vec<Value> = (0..self.latency as usize)
            .rev()
            .map(|i| bit(stage_valid.get(i).copied().unwrap_or(false)))
            .collect();
        self.w.change_vector(self.stages, bits)?;
        for s in in_sig {
            if let Some(&(id, width)) = self.ins.get(s.name) {
                self.w.change_vector(id, vector(s.value, width))?;
            }
        }
        for s in out_sig {
            if let Some(&(id, width)) = self.outs.get(s.name) {
                self.w.change_vector(id, vector(s.value, width))?;
            }
        }
        self.w.timestamp(cycle * 10 + 5)?;
        self.w.change_scalar(self.clk, Value::V0)?;
        Ok(())
    }

    /// Flush the writer (pass `&mut File` or `&mut Vec<u8>` to keep the sink).
    pub fn finish(mut self) -> io::Result<()> {
        self.w.flush()
    }
}

fn bit(b: bool) -> Value {
    if b {
        Value::V1
    } else {
        Value::V0
    }
}

fn vector(v: u64, width: u32) -> Vec<Value> {
    (0..width)
        .rev()
        .map(|i| bit(i < 64 && (v >> i) & 1 == 1))
        .collect()
}
