"""Targeting a raster fire's front: density (FF Eq. 13 generalised), tactics, the release rule.

**Density.** FF Eq. 13 sums one Gaussian per fire centre. For a raster fire we sum one Gaussian
per *front cell* c_i (``fire_front``), weighted by the tactic's w_i:

    D(q) = sum_i w_i exp(-|q - c_i|^2 / (2 sigma^2))                                    (13')

evaluated on the coverage grid by splatting the weights into the grid and a Gaussian filter
(exact up to the grid's discretisation). The Voronoi-Lloyd machinery is FF's unchanged: the
UAV's own cell (Eqs. 6-7), mass and centroid of D there (Eqs. 8-9). Deviation (the paper aims
at fire centres, which for a raster fire is burnt-out ground): the aim point is the front cell
of the own cell nearest that centroid, so a UAV always flies at burning edge cells.

**Tactics** (``mission.tactic``), as fire services use them:

* ``head`` -- head attack, fastest front first: w_i = (R_i / R_max)^p + w_min, with R_i the rate
  of spread toward cell i (PM Eq. 1 per direction). For uniform fuel, Byram's fireline
  intensity I = H w R is proportional to R, so this weights by intensity too ("rate of
  spread or fireline intensity"); p = 2 concentrates the fleet on the head.
* ``flank`` -- flank attack from an anchor point: the anchor is the slowest front cell (the
  heel, where the fire backs into the wind: safe, low intensity) chosen once, and
  w_i = exp(-(d_i - d_min) / L) + w_min with d_i the distance from the anchor. Cells near the
  anchor are put out first, so the nearest live front moves up both flanks toward the head,
  the way crews "anchor and flank".
* ``auto`` -- head or flank per fire (:func:`auto_choice`), from the fleet's own picture: the
  front cells are grouped into fires (cells within ``auto_link_m`` of each other), and a fire
  gets a head attack when the flame length at its head is below ``auto_max_flame_m``, else a
  flank attack with its own anchor. The head's rate of spread R is the largest ROS the fleet
  knows on that fire's front; Byram's fireline intensity I = H w R [kW/m] (H the fuel's heat
  content, w the fuel consumed per area: the fleet's prior for the fuel, default Anderson's
  fuel model 1, 0.74 t/acre = 0.166 kg/m^2) and Byram's flame length L = 0.0775 I^0.46 [m]
  (Andrews & Rothermel 1982, "Charts for interpreting wildland fire behavior characteristics",
  USDA FS GTR INT-131, Eq. for L). The limit is the fire services' guidance on direct attack
  (NWCG Fireline Handbook / Fire Behavior Field Reference Guide PMS 437, "fire suppression
  interpretations" after Andrews & Rothermel 1982): flame length < 4 ft (1.2 m) hand crews can
  attack the head; 4-8 ft (1.2-2.4 m) too intense for hand crews at the head, but engines,
  dozers and aircraft drops can be effective; > 8 ft control efforts at the head will probably
  be ineffective. The fleet drops ~2 t per pass, an aircraft drop: the default limit is 8 ft
  (2.44 m), i.e. for fuel model 1 a head slower than ~0.59 m/s. Until the fleet's picture has
  a rate of spread (PM Eq. 1; before that ``fire_front`` orders the front by distance, scaled
  to a nominal rate) the nominal rate decides; a fire whose front has no finite ROS gets a
  flank attack (anchor and flank is the doctrine when the head is unknown). The flank anchor
  of an ``auto`` fire is its slowest front cell at each step (the heel), not frozen once.

**Aims by airspace** (our addition; FF's UAVs stay in their Voronoi cells, ours leave theirs for
the heaviest front cell when their cell holds none). Near the end of a fire every UAV whose cell
holds no front cell aims at the same heaviest cell, and at the very end at the one cell left:
worcester_vt seed 1 (before this rule) had all 5 UAVs circling one cell at 100 m/s, and UAVs 0
and 4, sharing a layer of the old 4-layer stack, passed at 4.88 m (FF reports >= 10 m). The
avoider (:mod:`.separation`) predicts straight lines over 2 s; around a shared aim the UAVs
reverse every few tenths of a second, so it cannot be the only barrier. The altitude stack
(:func:`raster_layers`) keeps UAVs of different layers >= 10 m apart, but has 3 layers for
the defaults, so in a fleet of more than 3 ids modulo 3 share one. So a UAV does not aim
within ``aim_clear_m`` (60 m: the avoider's ``yield_m``, inside which it treats a right-of-way
peer as close) of the aim a peer published with its last state when that peer is
suppressing, has the right of way (lower id, as in the avoider) and shares its airspace
(:func:`shares_airspace`: layers at most ``airspace_vertical_m`` apart, the avoider's
``vertical_m``; for the defaults that is the same layer only). With no front cell farther than
that, it waits ``aim_clear_m`` from that aim on its own side (:func:`standoff_point`) and takes
the front as soon as the peer leaves it to refill. One UAV per layer (three for the defaults)
still work one point together.

**Release rule.** A UAV releases only when its own latest FireCells show at least
``min_burning_cells`` burning cells inside ``release_radius_m`` of its estimated position, and
no more of them at the position one control step ahead (it releases on the peak of the pass).
The world applies a drop at the true position at the next control instant, which is the
estimate's time; ``release_radius_m`` < the footprint leaves a margin for the EKF error.
Positions [m; map frame].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from fire_uav_common.constants import CellState
from fire_uav_common.scenario import TACTICS

from .coverage import Grid
from .errors import ConfigError
from .fire_front import FrontCells

__all__ = [
    "TACTICS",
    "TacticConfig",
    "aim_on_front",
    "aims_taken",
    "auto_choice",
    "byram_flame_length_m",
    "fire_groups",
    "burning_within",
    "choose_anchor",
    "direct_run_point",
    "front_density",
    "front_tangent",
    "free_front",
    "front_weights",
    "layer_height",
    "raster_layers",
    "release_now",
    "shares_airspace",
    "standoff_point",
]


_TRUNCATE = 3.0  # [sigma] Eq. 13' kernel cut-off


@dataclass(frozen=True)
class TacticConfig:
    tactic: str = "auto"  # head | flank | auto (the scenario default: docs/studies.md)
    sigma_m: float = 10.0  # [m] Eq. 13' kernel width
    head_power: float = 2.0  # [-] head attack: w = (R / R_max)^p
    flank_scale_m: float = 60.0  # [m] flank attack: decay length L from the anchor
    min_weight: float = 0.02  # [-] every front cell keeps this much weight
    min_burning_cells: int = 3  # [-] release rule
    release_radius_m: float = 16.0  # [m] release rule (drop footprint minus an EKF margin)
    direct_spread_m: float = 25.0  # [m] radius of the direct-run points around a track centre
    direct_points: int = 6  # [-] points of the direct-run circle (one per UAV id modulo this)
    layers: int = 3  # [-] altitude layers of the fleet over a raster fire (raster_layers)
    layer_step_m: float = 14.0  # [m] between layers (raster_layers: 10 m separation + 2 x 2 m)
    layer_top_m: float = 36.0  # [m above terrain] the highest layer (raster_layers)
    auto_max_flame_m: float = 2.44  # [m] auto: head attack below this head flame length (8 ft, NWCG)
    auto_heat_kj_kg: float = 18_608.0  # [kJ/kg] auto: fuel heat content H (8000 BTU/lb, Rothermel 1972)
    auto_fuel_kg_m2: float = 0.166  # [kg/m^2] auto: fuel consumed w (fuel model 1, 0.74 t/acre)
    auto_link_m: float = 100.0  # [m] auto: front cells closer than this belong to one fire (a front
    # broken up by drops stays one fire)
    aim_clear_m: float = 60.0  # [m] no aim within this of the aim of a right-of-way peer sharing the
    # airspace (aims_taken); 0: off
    airspace_vertical_m: float = 10.0  # [m] layers at most this far apart share the airspace (the
    # agent sets separation.vertical_m: the avoider's own conflict band)

    def __post_init__(self) -> None:
        if self.tactic not in TACTICS:
            raise ConfigError(f"tactic must be one of {list(TACTICS)}, got {self.tactic!r}")
        if not self.sigma_m > 0:
            raise ConfigError(f"tactic sigma_m must be > 0, got {self.sigma_m}")
        if not self.flank_scale_m > 0:
            raise ConfigError(f"tactic flank_scale_m must be > 0, got {self.flank_scale_m}")
        if self.min_burning_cells < 1:
            raise ConfigError(f"tactic min_burning_cells must be >= 1, got {self.min_burning_cells}")
        if not self.release_radius_m > 0:
            raise ConfigError(f"tactic release_radius_m must be > 0, got {self.release_radius_m}")
        if self.direct_points < 1:
            raise ConfigError(f"tactic direct_points must be >= 1, got {self.direct_points}")
        if self.layers < 1:
            raise ConfigError(f"tactic layers must be >= 1, got {self.layers}")
        for name in ("auto_max_flame_m", "auto_heat_kj_kg", "auto_fuel_kg_m2", "auto_link_m"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"tactic {name} must be > 0, got {getattr(self, name)}")
        if not self.layer_step_m >= 0:
            raise ConfigError(f"tactic layer_step_m must be >= 0, got {self.layer_step_m}")
        for name in ("aim_clear_m", "airspace_vertical_m"):
            if not getattr(self, name) >= 0:
                raise ConfigError(f"tactic {name} must be >= 0, got {getattr(self, name)}")
        bottom = self.layer_top_m - (self.layers - 1) * self.layer_step_m
        if not bottom > 0:
            raise ConfigError(
                f"tactic layers do not fit above the ground: {self.layers} layers {self.layer_step_m} m apart "
                f"below {self.layer_top_m} m put the lowest at {bottom:g} m"
            )

    def layer_height_m(self, uav_id: int) -> float:
        """Height [m above terrain] of ``uav_id``'s raster layer: ``layer_top_m`` down in steps of
        ``layer_step_m``, UAV id modulo ``layers``, the lowest id lowest (not from the flight height:
        the stack is bounded by the altimeter's range, see :func:`raster_layers`)."""
        return self.layer_top_m - self.layer_step_m * (self.layers - 1 - uav_id % self.layers)


# [m] |true height above terrain - command| in level flight inside the altimeter's range:
# p99 1.7 m, measured over grass_brush_hill (docs/suppression.md "Collisions")
TRACKING_ERROR_M = 2.0
MAX_LAYERS = 6


def raster_layers(
    collision_radius_m: float,
    altimeter_range_m: float,
    floor_m: float,
    tracking_error_m: float = TRACKING_ERROR_M,
    separation_m: float = 0.0,
) -> tuple[int, float, float]:
    """(layers, step [m], top [m above terrain]) of the raster altitude stack (our choice, not in FF).

    Two UAVs each on its own layer must stay ``separation_m`` (and at least the collision radius
    R) apart whatever their horizontal tracks: each holds its layer within e, the measured height
    tracking error, and the world's collision is 3-D, R between centres, so step = max(R,
    separation) + 2 e. The agent passes the avoider's vertical band (``separation.vertical_m``,
    10 m: FF's reported closest approach, and the height difference beyond which the avoider
    ignores a peer): UAVs on different layers are then never closer than 10 m and never the
    avoider's business, and only UAVs of one layer need keeping apart horizontally (by the
    avoider, and by not aiming at one point: module doc, "Aims by airspace"). Until this change
    the step was 2 R + e = 8 m: adjacent layers passed at 8.7-9.5 m over worcester_vt's fire, inside
    the avoider's band, and with 4 layers 0 and 4 of 5 UAVs shared one (4.88 m).

    The top layer is 2 e below the altimeter's range, so that a UAV there stays inside it with
    margin (above it the EKF's height runs on dead reckoning and the error grows: the > 2 m
    errors measured were all from the old 38.75 m layer, just under the 40 m range), the bottom
    one no lower than ``floor_m`` (the refill height, the lowest the fleet flies anyway). As many
    layers as fit, at most MAX_LAYERS: for the defaults (R 3 m, e 2 m, separation 10 m, range
    40 m, floor 7.5 m) 3 layers 14 m apart at 8, 22 and 36 m, UAV id modulo 3.
    """
    step = max(collision_radius_m, separation_m) + 2.0 * tracking_error_m
    top = altimeter_range_m - 2.0 * tracking_error_m
    if not top > floor_m:
        raise ConfigError(
            f"raster layers: the altimeter range minus twice the tracking error ({top:g} m) is not above "
            f"the floor ({floor_m:g} m)"
        )
    n = MAX_LAYERS if step <= 0 else min(MAX_LAYERS, 1 + int((top - floor_m) // step))
    return n, step, top


def layer_height(uav_id: int, flight_height_m: float, layers: int = 6, step_m: float = 3.5) -> float:
    """Flight height [m above terrain] of ``uav_id``: ``layers`` altitude layers ``step_m`` apart
    centred on the flight height (fire services separate aircraft over a fire by altitude); every
    objective that flies at the flight height (search, monitor, suppress, refill transit) uses it.
    Used by the FF mode (``GuidanceConfig.ff_layers``); a raster fire uses
    :meth:`TacticConfig.layer_height_m` (a stack top-down from below the altimeter's range).

    Our addition, not in FF: the Voronoi cells keep UAVs apart only while each flies inside its
    own cell, and over a fire they cross cells on drop and refill runs; at one common height two
    crossing UAVs collide (the world's 3-D collision model).
    """
    return flight_height_m + step_m * ((uav_id % layers) - (layers - 1) / 2.0)


def direct_run_point(centre_xy: tuple[float, float], uav_id: int, cfg: TacticConfig) -> tuple[float, float]:
    """Where a stalled UAV's direct run goes over a raster fire with no front: its own point on a
    circle of ``direct_spread_m`` around the track centre, ``direct_points`` points evenly spaced (25 m
    radius: neighbours 25 m apart), so that the fleet's runs do not converge on one point. Our
    choice; FF's direct run aims at the centre itself."""
    a = 2.0 * math.pi * (uav_id % cfg.direct_points) / cfg.direct_points
    return centre_xy[0] + cfg.direct_spread_m * math.cos(a), centre_xy[1] + cfg.direct_spread_m * math.sin(a)


def choose_anchor(front: FrontCells) -> tuple[float, float] | None:
    """The flank attack's anchor: the slowest front cell (lowest index among ties); None if no front."""
    if len(front) == 0:
        return None
    ros = np.where(np.isfinite(front.ros_mps), front.ros_mps, np.inf)
    k = int(np.argmin(ros)) if np.isfinite(ros).any() else 0
    return float(front.x_m[k]), float(front.y_m[k])


def byram_flame_length_m(ros_mps: float, cfg: TacticConfig) -> float:
    """Flame length [m] of a head spreading at ``ros_mps``: Byram I = H w R [kW/m], L = 0.0775 I^0.46."""
    intensity_kw_m = cfg.auto_heat_kj_kg * cfg.auto_fuel_kg_m2 * max(float(ros_mps), 0.0)
    return 0.0775 * intensity_kw_m**0.46


def fire_groups(front: FrontCells, link_m: float) -> np.ndarray:
    """Label per front cell: cells chained by gaps <= ``link_m`` [m] are one fire (0, 1, ... in order
    of their first cell).

    The pairs within ``link_m`` are cKDTree's (``query_pairs``: distance at most r); the fires are
    the connected components of that graph, found by min-label propagation with pointer jumping
    in numpy (a handful of passes over the pairs; scipy's sparse-graph route cost ~0.3 ms of
    per-call validation and conversions on fronts of ~200 cells). Each cell's label converges to
    the smallest index in its fire, so numbering fires by their smallest index is numbering them
    in order of their first cell."""
    n = len(front)
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    from scipy.spatial import cKDTree

    pairs = cKDTree(np.column_stack([front.x_m, front.y_m])).query_pairs(link_m, output_type="ndarray")
    a = np.concatenate([pairs[:, 0], pairs[:, 1]])
    b = np.concatenate([pairs[:, 1], pairs[:, 0]])
    lab = np.arange(n)
    while True:  # labels only fall and each stays an index of the cell's own fire: terminates
        new = lab.copy()
        np.minimum.at(new, a, lab[b])  # the smallest label among each cell and its neighbours
        new = new[new]  # pointer jumping: take the label's own label
        if np.array_equal(new, lab):  # constant along every pair: the smallest index of each fire
            break
        lab = new
    _, labels = np.unique(lab, return_inverse=True)
    return labels.astype(np.int64)


def auto_choice(ros_mps: np.ndarray, cfg: TacticConfig) -> str:
    """``head`` or ``flank`` for one fire from its front's ROS [m/s] (NaN unknown; module doc)."""
    ros = np.asarray(ros_mps, dtype=float)
    if not np.isfinite(ros).any():
        return "flank"
    return "head" if byram_flame_length_m(float(np.nanmax(ros)), cfg) < cfg.auto_max_flame_m else "flank"


def front_weights(
    front: FrontCells, cfg: TacticConfig, anchor_xy: tuple[float, float] | None = None
) -> np.ndarray:
    """w_i of Eq. 13' for every front cell (module doc); unknown ROS counts as the mean of the known.

    ``auto``: per fire (:func:`fire_groups`) the head or flank weights of :func:`auto_choice`, the
    flank anchor being that fire's slowest front cell (``anchor_xy`` is not used)."""
    n = len(front)
    if n == 0:
        return np.zeros(0)
    if cfg.tactic == "auto":
        import dataclasses

        w = np.zeros(n)
        labels = fire_groups(front, cfg.auto_link_m)
        for g in range(int(labels.max()) + 1):
            sel = labels == g
            part = FrontCells(
                front.x_m[sel], front.y_m[sel], front.state[sel], front.t_obs_s[sel], front.ros_mps[sel]
            )
            sub = dataclasses.replace(cfg, tactic=auto_choice(part.ros_mps, cfg))
            w[sel] = front_weights(part, sub, None)
        return w
    if cfg.tactic == "head":
        ros = np.asarray(front.ros_mps, dtype=float)
        ok = np.isfinite(ros)
        if not ok.any() or not np.nanmax(ros) > 0:
            return np.ones(n)
        if not ok.all():  # (np.where would take none of the mean when every cell is known)
            ros = np.where(ok, ros, np.nanmean(ros))
        return (np.clip(ros, 0.0, None) / np.nanmax(ros)) ** cfg.head_power + cfg.min_weight
    if anchor_xy is None:
        anchor_xy = choose_anchor(front)
    assert anchor_xy is not None
    d = np.hypot(front.x_m - anchor_xy[0], front.y_m - anchor_xy[1])
    return np.exp(-(d - d.min()) / cfg.flank_scale_m) + cfg.min_weight


def front_density(grid: Grid, front: FrontCells, weights: np.ndarray, sigma_m: float) -> np.ndarray:
    """Eq. 13' on ``grid.points`` (flattened like :func:`coverage.gaussian_density`)."""
    ny, nx = grid.shape
    res = grid.resolution_m
    dens = np.zeros((ny, nx))
    if len(front):
        j = np.clip(np.floor((front.x_m - grid.xs[0]) / res + 0.5).astype(int), 0, nx - 1)
        i = np.clip(np.floor((front.y_m - grid.ys[0]) / res + 0.5).astype(int), 0, ny - 1)
        s = sigma_m / res
        # the filter only on the window the kernel can reach (support: the splatted cells plus the
        # kernel radius int(truncate * s + 0.5)); outside it the filtered field is exactly zero, and
        # inside it every output sums the same taps in the same order as over the whole grid
        r = int(_TRUNCATE * s + 0.5) + 1
        i0, i1 = max(int(i.min()) - r, 0), min(int(i.max()) + r + 1, ny)
        j0, j1 = max(int(j.min()) - r, 0), min(int(j.max()) + r + 1, nx)
        win = np.zeros((i1 - i0, j1 - j0))
        np.add.at(win, (i - i0, j - j0), weights)
        from scipy.ndimage import gaussian_filter  # only a raster suppressor needs scipy (agent RSS)

        # gaussian_filter normalises its kernel: scale back to Eq. 13' (peak 1 per unit weight)
        dens[i0:i1, j0:j1] = gaussian_filter(win, s, mode="constant", truncate=_TRUNCATE) * (
            2.0 * math.pi * s * s
        )
    return dens.ravel()


def aim_on_front(
    centroid_xy: tuple[float, float] | None,
    front: FrontCells,
    weights: np.ndarray,
    in_cell: np.ndarray,
    free: np.ndarray | None = None,
) -> tuple[float, float] | None:
    """The aim point: the own-cell front cell nearest the Eq. 9 centroid; without one in the cell,
    the heaviest front cell (ties: nearest the centroid); None without a front.

    ``free`` (bool per front cell, default all): only these cells may be aimed at (cells near an
    aim a right-of-way peer sharing the airspace has taken are not, :func:`aims_taken`); None when
    no front cell is free."""
    if len(front) == 0:
        return None
    ok = np.ones(len(front), bool) if free is None else np.asarray(free, bool).reshape(-1)
    if not ok.any():
        return None
    w = np.where(ok, weights, -np.inf)
    mine = in_cell & ok
    cand = np.flatnonzero(mine) if mine.any() else np.flatnonzero(ok & (w >= w.max() * (1 - 1e-9)))
    if centroid_xy is None:
        k = cand[int(np.argmax(weights[cand]))]
    else:
        d = np.hypot(front.x_m[cand] - centroid_xy[0], front.y_m[cand] - centroid_xy[1])
        k = cand[int(np.argmin(d))]
    return float(front.x_m[k]), float(front.y_m[k])


def front_tangent(
    front: FrontCells,
    aim_xy: tuple[float, float],
    radius_m: float,
    min_cells: int = 5,
    max_aspect: float = 0.5,
) -> tuple[float, float] | None:
    """The front's direction at ``aim_xy``: the unit principal axis (either sign) of the front cells
    within ``radius_m`` of it, or None where that is no line: fewer than ``min_cells`` cells, or a
    minor-to-major spread ratio sqrt(lambda_2 / lambda_1) above ``max_aspect`` (a blob of cells, e.g.
    a spot fire or the front's tip folded back within the radius).

    The principal axis of the cells' scatter is the total-least-squares line through them (the
    eigenvector of their 2 x 2 covariance with the largest eigenvalue). A pattern drop's run is laid
    along it (``guidance.Guide``): fire services lay retardant and water lines along the fire's
    edge, anchored, not across it (module doc of :mod:`.guidance`, "drop run")."""
    if len(front) == 0 or not radius_m > 0:
        return None
    dx = front.x_m - aim_xy[0]
    dy = front.y_m - aim_xy[1]
    near = dx * dx + dy * dy <= radius_m * radius_m
    n = int(np.count_nonzero(near))
    if n < max(2, min_cells):
        return None
    x, y = dx[near], dy[near]
    x = x - x.mean()
    y = y - y.mean()
    cov = np.array([[np.dot(x, x), np.dot(x, y)], [np.dot(x, y), np.dot(y, y)]]) / n
    lam, vec = np.linalg.eigh(cov)  # ascending eigenvalues
    if not lam[1] > 0 or lam[0] > max_aspect * max_aspect * lam[1]:
        return None
    return float(vec[0, 1]), float(vec[1, 1])


def shares_airspace(uav_id: int, peer_id: int, cfg: TacticConfig) -> bool:
    """Whether two UAVs' raster layers are at most ``airspace_vertical_m`` apart (the same layer, and
    for the defaults also the adjacent ones: 8 m <= 10 m): the pairs that can pass within the
    avoider's vertical band over one aim point (module doc, "Aims by airspace")."""
    return abs(cfg.layer_height_m(uav_id) - cfg.layer_height_m(peer_id)) <= cfg.airspace_vertical_m


def aims_taken(uav_id: int, peers: list[tuple[int, bool, float, float]], cfg: TacticConfig) -> np.ndarray:
    """The aims [m; map] ``uav_id`` keeps ``aim_clear_m`` away from, (k, 2): of the peers (rows
    ``(peer_id, suppressing, x_m, y_m)``: the point the peer last published it steers at) with the
    right of way (lower id, as in :mod:`.separation`) that are suppressing and share the
    airspace (:func:`shares_airspace`). Non-finite points are skipped."""
    rows = [
        (x, y)
        for j, suppressing, x, y in peers
        if j < uav_id
        and suppressing
        and math.isfinite(x)
        and math.isfinite(y)
        and shares_airspace(uav_id, j, cfg)
    ]
    return np.array(rows, dtype=float).reshape(-1, 2)


def free_front(front: FrontCells, taken_xy: np.ndarray, clear_m: float) -> np.ndarray:
    """Bool per front cell: farther than ``clear_m`` [m] from every row of ``taken_xy``."""
    t = np.asarray(taken_xy, dtype=float).reshape(-1, 2)
    if len(front) == 0 or t.shape[0] == 0 or not clear_m > 0:
        return np.ones(len(front), bool)
    d2 = (front.x_m[:, None] - t[None, :, 0]) ** 2 + (front.y_m[:, None] - t[None, :, 1]) ** 2
    return np.all(d2 > clear_m * clear_m, axis=1)


def standoff_point(
    own_xy: tuple[float, float], near_xy: tuple[float, float], taken_xy: np.ndarray, clear_m: float
) -> tuple[float, float]:
    """Where a UAV whose every front cell is taken waits: ``clear_m`` [m] from the taken aim nearest
    ``near_xy`` (its Eq. 9 centroid), on the side of ``own_xy`` (straight +x of it when the UAV is
    over that aim). It keeps its water, and takes the front when that peer leaves it (to refill)."""
    t = np.asarray(taken_xy, dtype=float).reshape(-1, 2)
    k = int(np.argmin(np.hypot(t[:, 0] - near_xy[0], t[:, 1] - near_xy[1])))
    ax, ay = float(t[k, 0]), float(t[k, 1])
    dx, dy = own_xy[0] - ax, own_xy[1] - ay
    n = math.hypot(dx, dy)
    if n < 1e-6:
        dx, dy, n = 1.0, 0.0, 1.0
    return ax + clear_m * dx / n, ay + clear_m * dy / n


def burning_within(
    cells: tuple[np.ndarray, np.ndarray, np.ndarray] | None, xy: tuple[float, float], r_m: float
) -> int:
    """Burning cells of a FireCells sample (x_m, y_m, state) with centres within ``r_m`` of ``xy``."""
    if cells is None or len(cells[0]) == 0:
        return 0
    x, y, st = cells
    near = (x - xy[0]) ** 2 + (y - xy[1]) ** 2 <= r_m * r_m
    return int(np.count_nonzero(near & (st == CellState.BURNING)))


def release_now(
    cells: tuple[np.ndarray, np.ndarray, np.ndarray] | None,
    pos_xy: tuple[float, float],
    yaw_rad: float,
    step_m: float,
    cfg: TacticConfig,
) -> bool:
    """The release rule (module doc): enough burning cells under the footprint, and at the peak.

    ``step_m`` [m]: distance flown in one control step (speed x period), along ``yaw_rad``.
    """
    here = burning_within(cells, pos_xy, cfg.release_radius_m)
    if here < cfg.min_burning_cells:
        return False
    ahead = (pos_xy[0] + step_m * math.cos(yaw_rad), pos_xy[1] + step_m * math.sin(yaw_rad))
    return here >= burning_within(cells, ahead, cfg.release_radius_m)
