"""A parking lot: rows of parked cars, trees, hedges, light poles, kerbs, a wall, pedestrians.

The sensor stands on a mast in the main aisle (along x, centred on y = 0) and moves slowly
along it. Either side of the aisle two rows of bays stand back to back, their cars side by side
within a row and nose to tail across the two rows; beyond them a planted strip between kerbs
holds trees and light poles. On the right (y < 0) the strip is the lot's edge and holds a hedge;
on the left a service aisle follows, then a kerbside row of cars and long vehicles parked nose
to tail, a pavement and a building wall. Vehicles and pedestrians have boxes; the clutter
(trunks, canopies, hedges, poles, kerbs, wall) has none.
"""
import numpy as np

from . import meshes
from .lidar import ROAD_REFLECTIVITY, VERGE_REFLECTIVITY, Volume
from .scene import World

# A canopy's vertical semi-axis relative to its horizontal ones.
CANOPY_FLATNESS = 0.8
# Share of cars in bays that face away from the main aisle (parked nose first in the first row).
NOSE_IN_SHARE = 0.7
# m, hedge segments along the lot's edge and the breaks between them
HEDGE_SEGMENT = (6.0, 15.0)
HEDGE_BREAK = (0.5, 2.0)


class ParkingLot(World):
    def __init__(self, config, duration, seed, class_meshes=None):
        super().__init__(config, duration, seed, class_meshes)
        self.lot = lot = config.parking_lot
        for name in ("side_gap", "nose_gap", "tree_spacing", "trunk_height", "canopy_radius",
                     "hedge_height"):
            value = getattr(lot, name)
            if len(value) != 2 or value[0] > value[1]:
                raise ValueError(f"parking_lot.{name}: expected [low, high] with low <= high, "
                                 f"got {list(value)}")
        if len(lot.kerb_size) != 2:
            raise ValueError(f"parking_lot.kerb_size: expected [width, height], got "
                             f"{list(lot.kerb_size)}")
        travel = lot.sensor_speed * duration
        if travel > lot.length:
            raise ValueError(f"parking_lot: the mast would travel {travel:g} m in {duration:g} s, "
                             f"beyond the lot's length of {lot.length:g} m (lower "
                             "parking_lot.sensor_speed or the duration)")
        self.half_aisle = lot.aisle_width / 2.0
        self.strip_start = self.half_aisle + 2.0 * lot.bay_depth   # |y| of the strip's inner kerb
        self.strip_end = self.strip_start + lot.strip_width
        self.kerbside_start = self.strip_end + lot.aisle_width      # y of the kerbside row
        for side in (-1.0, 1.0):
            self._spawn_bays(side)
            self._spawn_strip(side)
        self._spawn_hedge()
        self._spawn_kerbside_row_and_wall()
        self._spawn_pedestrians()

    @property
    def sensor_height(self):
        return self.lot.mast_height

    def ego_position(self, t):
        return np.array([self.lot.sensor_speed * (t - self.duration / 2.0), 0.0,
                         self.lot.mast_height])

    # --- spawning ------------------------------------------------------------------------
    def _uniform(self, low_high):
        return self.rng.uniform(*low_high)

    def _vehicle_mesh(self, weights):
        names = list(weights)
        p = np.array([weights[n] for n in names], float)
        label = names[self.rng.choice(len(names), p=p / p.sum())]
        variation = self.config.traffic.size_variation
        return label, self.class_meshes[label].scaled(
            1.0 + self.rng.uniform(-variation, variation, 3))

    def _spawn_bays(self, side):
        """Two rows back to back: side by side along x, nose to tail across the rows."""
        lot = self.lot
        meeting = self.half_aisle + lot.bay_depth  # |y| where the two rows' cars meet
        for row in (0, 1):
            x = -lot.length / 2.0
            while True:
                label, mesh = self._vehicle_mesh(lot.bay_class_weights)
                length, width = mesh.extents[:2]
                if x + width > lot.length / 2.0:
                    break
                if self.rng.random() < lot.occupancy:
                    half_gap = self._uniform(lot.nose_gap) / 2.0
                    offset = (meeting - half_gap - length / 2.0 if row == 0
                              else meeting + half_gap + length / 2.0)
                    nose_away_from_aisle = self.rng.random() < NOSE_IN_SHARE
                    yaw = side * np.pi / 2.0 * (1.0 if nose_away_from_aisle else -1.0)
                    self._actor(label, x + width / 2.0, side * offset, 0.0, yaw,
                                lot.parked_yaw_noise_deg, mesh=mesh)
                x += width + self._uniform(lot.side_gap)

    def _spawn_strip(self, side):
        """Kerbs on both edges of the planted strip, trees and light poles on it."""
        lot = self.lot
        kerb_width, kerb_height = lot.kerb_size
        for edge in (self.strip_start + kerb_width / 2.0, self.strip_end - kerb_width / 2.0):
            self._actor(None, 0.0, side * edge, 0.0, 0.0, 0.0,
                        mesh=meshes.kerb(lot.length, kerb_width, kerb_height))
        middle = (self.strip_start + self.strip_end) / 2.0
        x = -lot.length / 2.0 + self.rng.uniform(0.0, lot.tree_spacing[0])
        while x < lot.length / 2.0:
            self._tree(x, side * (middle + self.rng.uniform(-0.3, 0.3)))
            x += self._uniform(lot.tree_spacing)
        pole_y = side * (self.strip_start + kerb_width + 0.4)
        for x in np.arange(-lot.length / 2.0 + lot.light_pole_spacing / 2.0, lot.length / 2.0,
                           lot.light_pole_spacing):
            self._actor(None, x, pole_y, 0.0, 0.0, 0.0, mesh=meshes.pole(lot.light_pole_height))

    def _tree(self, x, y):
        lot = self.lot
        trunk_height = self._uniform(lot.trunk_height)
        radius = np.array([self._uniform(lot.canopy_radius), self._uniform(lot.canopy_radius)])
        half_size = np.append(radius, CANOPY_FLATNESS * radius.mean())
        # The trunk reaches into the canopy, as a real one carries it.
        self._actor(None, x, y, 0.0, 0.0, 0.0,
                    mesh=meshes.trunk(trunk_height + half_size[2], lot.trunk_radius))
        self.volumes.append(Volume(np.array([x, y, trunk_height + half_size[2]]), half_size,
                                   is_box=False, density=lot.canopy_density))

    def _spawn_hedge(self):
        """Along the right-hand strip, the lot's edge: segments of varying height."""
        lot = self.lot
        y = -(self.strip_start + self.strip_end) / 2.0
        x = -lot.length / 2.0
        while x < lot.length / 2.0:
            length = min(self._uniform(HEDGE_SEGMENT), lot.length / 2.0 - x)
            height = self._uniform(lot.hedge_height)
            self.volumes.append(Volume(np.array([x + length / 2.0, y, height / 2.0]),
                                       np.array([length / 2.0, lot.hedge_width / 2.0,
                                                 height / 2.0]),
                                       is_box=True, density=lot.hedge_density))
            x += length + self._uniform(HEDGE_BREAK)

    def _spawn_kerbside_row_and_wall(self):
        """Left of the service aisle: vehicles parked along x nose to tail, then the wall."""
        lot = self.lot
        widest = 0.0
        x = -lot.length / 2.0
        while True:
            label, mesh = self._vehicle_mesh(lot.kerbside_class_weights)
            length, width = mesh.extents[:2]
            if x + length > lot.length / 2.0:
                break
            widest = max(widest, width)
            if self.rng.random() < lot.occupancy:
                yaw = 0.0 if self.rng.random() < 0.5 else np.pi
                self._actor(label, x + length / 2.0,
                            self.kerbside_start + 0.3 + width / 2.0, 0.0, yaw,
                            lot.parked_yaw_noise_deg, mesh=mesh)
            x += length + self._uniform(lot.nose_gap)
        wall = meshes.wall(lot.length, lot.wall_height)
        self.wall_y = self.kerbside_start + 0.3 + widest + lot.pavement_width + wall.extents[1] / 2
        self._actor(None, 0.0, self.wall_y, 0.0, 0.0, 0.0, mesh=wall)

    def _spawn_pedestrians(self):
        """Walking along the main aisle (clear of the mast) and the service aisle."""
        lot = self.lot
        for _ in range(lot.pedestrians):
            if self.rng.random() < 0.6:
                y = self.rng.choice([-1.0, 1.0]) * self.rng.uniform(1.0, self.half_aisle - 0.5)
            else:
                y = self.strip_end + self.rng.uniform(1.0, lot.aisle_width - 1.0)
            direction = self.rng.choice([-1.0, 1.0])
            self._actor("Pedestrian", self.rng.uniform(-lot.length / 2.0, lot.length / 2.0), y,
                        direction * lot.pedestrian_speed, 0.0 if direction > 0 else np.pi, 10.0)

    # --- observation ---------------------------------------------------------------------
    def reflectivity(self, x, y):
        """Asphalt, with grass on the planted strips and beyond the lot's right-hand edge."""
        planted = (np.abs(y) >= self.strip_start) & (np.abs(y) <= self.strip_end)
        beyond_edge = y < -self.strip_end
        return np.where(planted | beyond_edge, VERGE_REFLECTIVITY, ROAD_REFLECTIVITY)

    def ground_reflectivity(self, t):
        ego_x, ego_y = self.ego_position(t)[:2]
        return lambda x, y: self.reflectivity(x + ego_x, y + ego_y)
