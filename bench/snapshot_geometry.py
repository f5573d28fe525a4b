"""The list geometry that the snapshot-counting scripts (list_layout_memory.py,
cluster_pair_counts.py) share: the spacing, smoothing length, skin and cells per support of the
run whose snapshots they read, as the solver takes them (h = coef_h sqrt(3) dp, support 2h,
reach = support x (1 + skin), cells of reach / n)."""


def add_geometry_args(parser):
    parser.add_argument("--dp", type=float, default=0.02)
    parser.add_argument("--coef-h", type=float, default=1.0)
    parser.add_argument("--skin", type=float, default=0.1)
    parser.add_argument("--n", type=int, default=2, help="cells per support")
    return parser
