"""The plant FMU with fmpy alone: 2 s of u = 0.8 sin(2 pi t) V from rest at 150 mm (no controller)."""
import sys
import numpy as np
from fmpy import simulate_fmu
fmu = sys.argv[1] if len(sys.argv) > 1 else "build/LinearMotorFeedDrive.fmu"
t = np.arange(0.0, 2.0 + 1e-9, 5e-4)                     # the inputs at the 0.5 ms samples
inputs = np.array(list(zip(t, 0.8 * np.sin(2 * np.pi * t), 0 * t, strict=True)), dtype=[("time", float), ("u", float), ("F_ext", float)])
res = simulate_fmu(fmu, stop_time=2.0, input=inputs, output=["x", "v", "i", "F_friction"], output_interval=5e-4)
print(f"x from {res['x'].min() * 1e3:.1f} to {res['x'].max() * 1e3:.1f} mm, |v| up to {np.abs(res['v']).max() * 1e3:.0f} mm/s, "
      f"|i| up to {np.abs(res['i']).max():.2f} A, friction up to {np.abs(res['F_friction']).max():.1f} N")
