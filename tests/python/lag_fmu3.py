"""An FMI 3.0 Co-Simulation FMU made by another exporter (pythonfmu3 from PyPI) for the
importer's tests: a first-order lag of a sine, y' = (sin(2 pi f t) - y) / tau, advanced by
ten explicit substeps in each communication step.

    pythonfmu3 build -f tests/python/lag_fmu3.py --dest DIR   # writes DIR/Lag.fmu
"""
import math

from pythonfmu3 import Fmi3Causality, Fmi3Slave, Fmi3Variability, Float64


class Lag(Fmi3Slave):
    author = "tbi tests"
    description = "First-order lag of a sine"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.tau = 0.2
        self.f = 1.5
        self.y = 0.0
        self.time = 0.0
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=Fmi3Variability.continuous))
        self.register_variable(Float64("tau", causality=Fmi3Causality.parameter,
                                       variability=Fmi3Variability.fixed))
        self.register_variable(Float64("f", causality=Fmi3Causality.parameter,
                                       variability=Fmi3Variability.fixed))
        self.register_variable(Float64("y", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.continuous,
                                       initial="exact", start=0.0))

    def do_step(self, current_time, step_size):
        n = 10
        h = step_size / n
        t = current_time
        for _ in range(n):
            self.y += h * (math.sin(2 * math.pi * self.f * t) - self.y) / self.tau
            t += h
        self.time = current_time + step_size
        return True
