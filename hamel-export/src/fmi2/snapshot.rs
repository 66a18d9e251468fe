//! The FMU state (`canGetAndSetFMUstate`, `canSerializeFMUstate`): everything an instance
//! computes from — the mode, the time, the state, the inputs, the parameters, the
//! experiment's settings and Co-Simulation's memory — so that an importer can go back to a
//! point and run from it again (a master that rejects a communication step), to the same
//! bits. Serialized as a tag, the sizes, and the values in little-endian order; bytes of
//! another model, of other sizes or with a value that is not a number are refused.

use super::instance::{Experiment, Instance, Refusal, Stepping};
use super::modes::Mode;
use crate::model::Model;
use hamel_runtime::{HamelSystem, Parameters};

/// A saved instance.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    pub mode: Mode,
    pub t: f64,
    pub x: Vec<f64>,
    pub u: Vec<f64>,
    pub parameters: Vec<f64>,
    pub experiment: Experiment,
    pub method: usize,
    pub step: f64,
    pub stepping: Stepping,
}

/// The first bytes of a serialized state.
const TAG: &[u8; 8] = b"hamelfm1";

const MODES: [Mode; 8] = [
    Mode::Instantiated,
    Mode::Initialization,
    Mode::Event,
    Mode::Continuous,
    Mode::StepComplete,
    Mode::StepFailed,
    Mode::Terminated,
    Mode::Error,
];

impl<M: Model> Instance<M> {
    /// The instance as it is now.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            mode: self.mode,
            t: self.t,
            x: self.x.as_ref().to_vec(),
            u: self.u.as_ref().to_vec(),
            parameters: <M::System as Parameters>::NAMES
                .iter()
                .map(|n| self.system.get(n).unwrap_or(f64::NAN))
                .collect(),
            experiment: self.experiment,
            method: self.method,
            step: self.step,
            stepping: self.stepping,
        }
    }

    /// The instance as it was when `snapshot` was taken (of this model: the sizes checked).
    pub fn restore(&mut self, snapshot: &Snapshot) -> Result<(), Refusal> {
        let s = self.table.sizes;
        if (
            snapshot.x.len(),
            snapshot.u.len(),
            snapshot.parameters.len(),
        ) != (s.nx, s.nu, s.np)
        {
            return Err(Refusal::error(
                "the FMU state is of another model (its sizes differ)",
            ));
        }
        for (name, value) in <M::System as Parameters>::NAMES
            .iter()
            .zip(&snapshot.parameters)
        {
            self.system
                .set(name, *value)
                .map_err(|e| Refusal::error(format!("the FMU state's parameters: {e}")))?;
        }
        self.prepare();
        self.mode = snapshot.mode;
        self.t = snapshot.t;
        self.x.as_mut().copy_from_slice(&snapshot.x);
        self.u.as_mut().copy_from_slice(&snapshot.u);
        self.experiment = snapshot.experiment;
        self.method = snapshot.method;
        self.step = snapshot.step;
        self.stepping = snapshot.stepping;
        Ok(())
    }
}

impl Snapshot {
    /// The serialized bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = TAG.to_vec();
        let mut count = |n: usize| out.extend_from_slice(&(n as u64).to_le_bytes());
        count(self.x.len());
        count(self.u.len());
        count(self.parameters.len());
        let mode = MODES.iter().position(|m| *m == self.mode).unwrap_or(0);
        let e = &self.experiment;
        let st = &self.stepping;
        let head = [
            mode as f64,
            self.t,
            e.tolerance.unwrap_or(f64::NAN),
            e.start,
            e.stop.unwrap_or(f64::NAN),
            self.method as f64,
            self.step,
            st.initial_step.unwrap_or(f64::NAN),
            st.last_successful_time,
            if st.terminated { 1.0 } else { 0.0 },
        ];
        let values = head
            .iter()
            .chain(&self.x)
            .chain(&self.u)
            .chain(&self.parameters);
        for v in values {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    /// A snapshot from bytes [`Snapshot::to_bytes`] wrote for a model of these sizes.
    pub fn from_bytes(bytes: &[u8], sizes: (usize, usize, usize)) -> Result<Snapshot, Refusal> {
        let refuse = |why: &str| Refusal::error(format!("the serialized FMU state {why}"));
        let rest = bytes
            .strip_prefix(TAG.as_slice())
            .ok_or_else(|| refuse("is not one of this FMU's"))?;
        let words: Vec<[u8; 8]> = rest
            .chunks(8)
            .map(|c| c.try_into().map_err(|_| refuse("is cut short")))
            .collect::<Result<_, _>>()?;
        let count = |i: usize| words.get(i).map(|w| u64::from_le_bytes(*w) as usize);
        let (nx, nu, np) = sizes;
        if (count(0), count(1), count(2)) != (Some(nx), Some(nu), Some(np)) {
            return Err(refuse("is of another model (its sizes differ)"));
        }
        let values: Vec<f64> = words[3..].iter().map(|w| f64::from_le_bytes(*w)).collect();
        if values.len() != 10 + nx + nu + np {
            return Err(refuse("has the wrong length"));
        }
        let optional = |v: f64| (!v.is_nan()).then_some(v);
        let mode = MODES
            .get(values[0] as usize)
            .copied()
            .filter(|_| values[0].fract() == 0.0 && values[0] >= 0.0)
            .ok_or_else(|| refuse("names no mode"))?;
        let method = values[5] as usize;
        if values[5].fract() != 0.0 || method >= super::variables::INTEGRATORS.len() {
            return Err(refuse("names no integrator"));
        }
        let (x, rest) = values[10..].split_at(nx);
        let (u, parameters) = rest.split_at(nu);
        let finite = [values[1], values[3], values[6], values[8]];
        if finite
            .iter()
            .chain(x)
            .chain(u)
            .chain(parameters)
            .any(|v| !v.is_finite())
        {
            return Err(refuse("holds a value that is not a finite number"));
        }
        Ok(Snapshot {
            mode,
            t: values[1],
            x: x.to_vec(),
            u: u.to_vec(),
            parameters: parameters.to_vec(),
            experiment: Experiment {
                tolerance: optional(values[2]),
                start: values[3],
                stop: optional(values[4]),
            },
            method,
            step: values[6],
            stepping: Stepping {
                initial_step: optional(values[7]),
                last_successful_time: values[8],
                terminated: values[9] != 0.0,
            },
        })
    }
}

/// The sizes of `M`'s state, inputs and parameters.
pub fn sizes<M: Model>() -> (usize, usize, usize) {
    (
        <M::System as HamelSystem>::STATE.len(),
        <M::System as HamelSystem>::INPUTS.len(),
        <M::System as Parameters>::NAMES.len(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_give_back_the_snapshot_and_refuse_what_is_not_one() {
        let snapshot = Snapshot {
            mode: Mode::StepComplete,
            t: 0.25,
            x: vec![1.0, -2.0, 3.5],
            u: vec![0.1],
            parameters: vec![9.81, 0.5],
            experiment: Experiment {
                tolerance: Some(1e-8),
                start: 0.0,
                stop: None,
            },
            method: 2,
            step: 1e-3,
            stepping: Stepping {
                initial_step: Some(0.004),
                last_successful_time: 0.25,
                terminated: false,
            },
        };
        let bytes = snapshot.to_bytes();
        assert_eq!(
            Snapshot::from_bytes(&bytes, (3, 1, 2)),
            Ok(snapshot.clone())
        );
        assert!(Snapshot::from_bytes(&bytes, (3, 1, 3)).is_err());
        assert!(Snapshot::from_bytes(&bytes[..bytes.len() - 3], (3, 1, 2)).is_err());
        assert!(Snapshot::from_bytes(b"something else", (3, 1, 2)).is_err());
        let mut nan = bytes.clone();
        let at = 8 + 3 * 8 + 10 * 8;
        nan[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
        assert!(Snapshot::from_bytes(&nan, (3, 1, 2)).is_err());
    }
}
