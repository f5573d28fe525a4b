"""Figure 5 of the paper (section 5.2): real wall time of a step (the longest time any device
takes to update its particles' physical quantity, forces + integration) against the ideal one
(the mean over devices) with the simple load balancer, which moves one cell slice from the
slower to the faster neighbour every step. The paper finds the gap acceptable, and shrinking
as the particle count grows.

Usage: python3 plots/fig5.py [--results results/multi-gpu] [--out plots/out]
"""
import multigpu
import sphplot

NAME = "fig5"

if __name__ == "__main__":
    sphplot.main_guard(NAME, lambda: multigpu.real_vs_ideal(NAME, "simple", 5))
