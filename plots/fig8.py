"""Figure 8 of the paper (section 5.2): real wall time of a step (the longest time any device
takes to update its particles' physical quantity, forces + integration) against the ideal one
(the mean over devices) with the threshold load balancer (equations 3 to 6), which moves a
slice only when that narrows the time gap between neighbouring devices.

Usage: python3 plots/fig8.py [--results results/multi-gpu] [--out plots/out]
"""
import multigpu
import sphplot

NAME = "fig8"

if __name__ == "__main__":
    sphplot.main_guard(NAME, lambda: multigpu.real_vs_ideal(NAME, "threshold", 8))
