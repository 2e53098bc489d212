"""What a sampled controller measures: an encoder's quantisation, noise with a seed, a delay of k samples, the
velocity read from a tachometer (the plant's q̇) or by discrete difference and a first-order low-pass.

The chain, per joint, built from Drake's blocks by :func:`add_sensors`::

    q ─ MatrixGain a ─ RotaryEncoders (N counts/rev) ─ MatrixGain 1/a ─ Adder ← MatrixGain σ ← RandomSource (h)
                                                        └─ sensor_sampling (discrete, period h) → [q_m, q̇_m]

* **encoder** (Drake's ``RotaryEncoders``: ⌊θ N / 2π⌋ · 2π / N of the angle θ it reads): N counts per revolution
  of the motor (θ = G q: a resolution of 2π/(N |G|) rad at the joint) or of the joint (θ = q); a prismatic joint's
  encoder on the joint side counts N per metre (θ = 2π q);
* **noise**: a Gaussian of standard deviation σ (rad or m) on the position, from Drake's ``RandomSource`` sampled
  every period, its seed the run's (the same seed, the same run);
* **sensor_sampling**: one discrete Drake ``LinearSystem`` of period h that, at each sample t_k, takes the position
  q_s(t_k) (and q̇(t_k)) into a shift register and puts out the sample of k periods before, q_m = q_s(t_{k−d}), and the
  velocity: the tachometer's q̇(t_{k−d}) (``"state"``), or the backward difference of the held positions through a
  first-order low-pass of cutoff f_c, v_k = a v_{k−1} + (1 − a)(q_m,k − q_m,k−1)/h with a = exp(−2π f_c h) (the
  exact discretisation; no cutoff: a = 0, the difference alone) (``"difference"``). Drake's ``DiscreteTimeDelay``,
  ``DiscreteDerivative`` and a discrete filter in series would each add one sample: Drake updates every discrete
  block at t_k from the others' values before t_k. One system keeps the whole chain within its sample, as a drive's
  firmware does within its interrupt, so a delay of d samples is d samples, exactly (tests/test_servo.py checks its
  phase lag ω h (d + ½) against the analytic one, the ½ being the hold's).

Its state starts as if the arm had stood at (or moved at the constant rate of) its start state forever
(:meth:`SensorDesign.initial_state`), so that nothing jumps at t = 0.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from pydrake.systems.framework import DiagramBuilder, OutputPort
    from pydrake.systems.primitives import LinearSystem

__all__ = ["ENCODER_SIDES", "VELOCITY_SOURCES", "SensorDesign", "add_sensors", "encoder_scale"]

#: Where an encoder sits: on the motor (before the gearbox) or on the joint.
ENCODER_SIDES = ("motor", "joint")
#: Where the measured velocity comes from: a tachometer (the plant's q̇) or the difference of encoder positions.
VELOCITY_SOURCES = ("state", "difference")


def encoder_scale(side: str, gear_ratio: ArrayLike, revolute: ArrayLike) -> NDArray[np.float64]:
    """a per joint: the encoder's angle θ = a·q (rad per rad or m): G on the motor side, 1 on a revolute joint's, 2π
    on a prismatic joint's (N counts per metre)."""
    if side not in ENCODER_SIDES:
        raise ValueError(f"encoder side {side!r} is not allowed; allowed: {', '.join(ENCODER_SIDES)}")
    if side == "motor":
        return np.asarray(gear_ratio, dtype=float).copy()
    return np.where(np.asarray(revolute, dtype=bool), 1.0, 2 * np.pi)


@dataclass(frozen=True)
class SensorDesign:
    """The sensors of a sampled controller (module docstring): ``period`` h (s), encoder ``counts`` N per revolution
    (``None``: the exact position) at ``scale`` a ``(n,)`` (:func:`encoder_scale`), ``velocity`` (one of
    :data:`VELOCITY_SOURCES`), its low-pass ``cutoff`` (Hz; ``None``: none), position ``noise`` σ (rad or m),
    ``seed`` and ``delay`` d (samples)."""

    period: float
    counts: int | None
    scale: NDArray[np.float64]
    velocity: str = "state"
    cutoff: float | None = None
    noise: float = 0.0
    delay: int = 0

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.scale.size)

    @property
    def resolution(self) -> NDArray[np.float64] | None:
        """The encoder's step at the joint, 2π/(N |a|) (rad or m), ``(n,)``; ``None`` without one."""
        return None if self.counts is None else 2 * np.pi / (self.counts * np.abs(self.scale))

    def quantize(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """What the encoder reads for positions ``q`` ``(..., n)``: RotaryEncoders' ⌊a q N/2π⌋·2π/(N a)."""
        if self.counts is None:
            return q
        step = 2 * np.pi / self.counts
        return np.floor(self.scale * q / step) * step / self.scale

    @property
    def _filter(self) -> float:
        """a = exp(−2π f_c h) of the velocity's low-pass (0: none)."""
        return 0.0 if self.cutoff is None else float(np.exp(-2 * np.pi * self.cutoff * self.period))

    def _sizes(self) -> tuple[int, int, int]:
        """Per joint: (position register, velocity register, filter) state sizes."""
        d = self.delay
        return (d + 2, 0, 1) if self.velocity == "difference" else (d + 1, d + 1, 0)

    def sampling_system(self) -> LinearSystem:
        """``sensor_sampling``: the discrete ``LinearSystem`` (period h) of input [q_s (n), q (n), q̇ (n)] and output
        [q_m (n), q̇_m (n)] (module docstring), block by block per joint."""
        from pydrake.systems.primitives import LinearSystem

        n, d, h = self.n, self.delay, self.period
        npos, nvel, nfil = self._sizes()
        per = npos + nvel + nfil
        a_mat, b_mat, c_mat = np.zeros((n * per, n * per)), np.zeros((n * per, 3 * n)), np.zeros((2 * n, n * per))
        alpha = self._filter
        for i in range(n):
            r = i * per  # r … r + npos − 1: positions q_s(t_k), q_s(t_{k−1}), …
            b_mat[r, i] = 1.0
            for j in range(1, npos):
                a_mat[r + j, r + j - 1] = 1.0
            c_mat[i, r + d] = 1.0
            if self.velocity == "state":
                s = r + npos
                b_mat[s, 2 * n + i] = 1.0
                for j in range(1, nvel):
                    a_mat[s + j, s + j - 1] = 1.0
                c_mat[n + i, s + d] = 1.0
            else:  # v' = a v + (1 − a)(r_d' − r_{d+1}')/h with r_d' = (u if d == 0 else r_{d−1}) and r_{d+1}' = r_d
                f = r + npos
                a_mat[f, f] = alpha
                gain = (1 - alpha) / h
                if d == 0:
                    b_mat[f, i] += gain
                else:
                    a_mat[f, r + d - 1] += gain
                a_mat[f, r + d] -= gain
                c_mat[n + i, f] = 1.0
        return LinearSystem(a_mat, b_mat, c_mat, np.zeros((2 * n, 3 * n)), h)

    def initial_state(self, q0: ArrayLike, v0: ArrayLike) -> NDArray[np.float64]:
        """``sensor_sampling``'s state for a start at ``q0`` moving at ``v0`` (each ``(n,)``) since ever: the
        registers hold the encoder's readings of q0 − j h v0 and q̇ = v0, the filter v0."""
        q0, v0 = np.asarray(q0, dtype=float), np.asarray(v0, dtype=float)
        npos, nvel, nfil = self._sizes()
        history = self.quantize(q0 - v0 * self.period * np.arange(npos)[:, None]).T  # (n, npos)
        blocks = [history]
        if nvel:
            blocks.append(np.repeat(v0[:, None], nvel, axis=1))
        if nfil:
            blocks.append(v0[:, None])
        return np.hstack(blocks).ravel()


def add_sensors(builder: DiagramBuilder, state: OutputPort, design: SensorDesign) -> LinearSystem:
    """The sensor chain of ``design`` on the plant's ``state`` [q, q̇] (module docstring); its ``sensor_sampling``
    system, whose output is the measured [q_m, q̇_m] and whose state :meth:`SensorDesign.initial_state` gives."""
    from pydrake.common import RandomDistribution
    from pydrake.systems.primitives import Adder, MatrixGain, Multiplexer, RandomSource
    from pydrake.systems.sensors import RotaryEncoders

    n = design.n
    select = builder.AddNamedSystem("joint_positions", MatrixGain(np.hstack([np.eye(n), np.zeros((n, n))])))
    builder.Connect(state, select.get_input_port())
    position = select.get_output_port()
    if design.counts is not None:
        to_encoder = builder.AddNamedSystem("encoder_angle", MatrixGain(np.diag(design.scale)))
        encoder = builder.AddNamedSystem("encoders", RotaryEncoders([design.counts] * n))
        from_encoder = builder.AddNamedSystem("encoder_position", MatrixGain(np.diag(1.0 / design.scale)))
        builder.Connect(position, to_encoder.get_input_port())
        builder.Connect(to_encoder.get_output_port(), encoder.get_input_port())
        builder.Connect(encoder.get_output_port(), from_encoder.get_input_port())
        position = from_encoder.get_output_port()
    if design.noise > 0:
        source = builder.AddNamedSystem("noise_source", RandomSource(RandomDistribution.kGaussian, n, design.period))
        sigma = builder.AddNamedSystem("noise", MatrixGain(design.noise * np.eye(n)))
        noisy = builder.AddNamedSystem("noisy_position", Adder(2, n))
        builder.Connect(source.get_output_port(), sigma.get_input_port())
        builder.Connect(position, noisy.get_input_port(0))
        builder.Connect(sigma.get_output_port(), noisy.get_input_port(1))
        position = noisy.get_output_port()
    inputs = builder.AddNamedSystem("sensor_inputs", Multiplexer([n, 2 * n]))
    builder.Connect(position, inputs.get_input_port(0))
    builder.Connect(state, inputs.get_input_port(1))
    sampling = design.sampling_system()
    builder.AddNamedSystem("sensor_sampling", sampling)
    builder.Connect(inputs.get_output_port(), sampling.get_input_port())
    return sampling
