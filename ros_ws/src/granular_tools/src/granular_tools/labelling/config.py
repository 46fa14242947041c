"""Settings of the labelling tool; config/labelling.yaml lays its values over these defaults."""
import dataclasses
import typing

from ..config_loading import ConfigError, bounded, load_yaml_over


@dataclasses.dataclass(frozen=True)
class ClassSettings:
    size: typing.List[float] = bounded(factory=lambda: [4.5, 1.8, 1.5], above=0.0)  # l w h, m
    colour: typing.List[float] = bounded(factory=lambda: [0.8, 0.8, 0.8], at_least=0.0,
                                         at_most=1.0)  # r g b


@dataclasses.dataclass(frozen=True)
class HandleSettings:
    length: float = bounded(0.8, above=0.0)  # m: arrow on each face of the selected box
    width: float = bounded(0.15, above=0.0)  # m: the arrow's shaft


# KITTI's classes, then the simulator's: (length, width, height) m, (r, g, b). The vehicles'
# sizes are config/cuboids.yaml's priors.
_CLASSES = (
    ("Car", (3.88, 1.63, 1.53), (0.2, 0.6, 1.0)), ("Van", (5.07, 1.90, 2.21), (0.3, 0.9, 0.3)),
    ("Truck", (10.14, 2.59, 3.25), (0.75, 0.45, 1.0)),
    ("Pedestrian", (0.8, 0.6, 1.75), (0.2, 1.0, 1.0)),
    ("Person_sitting", (0.8, 0.6, 1.3), (0.5, 1.0, 0.8)),
    ("Cyclist", (1.75, 0.6, 1.7), (1.0, 0.4, 0.7)), ("Tram", (15.0, 2.6, 3.5), (1.0, 0.95, 0.2)),
    ("Misc", (1.5, 1.5, 1.5), (0.8, 0.8, 0.8)),
    ("Sedan", (4.60, 1.82, 1.45), (0.2, 0.6, 1.0)), ("SUV", (4.80, 1.94, 1.80), (0.3, 0.9, 0.3)),
    ("Hatchback", (4.10, 1.78, 1.50), (1.0, 0.6, 0.1)),
    ("Jeep", (4.42, 1.96, 1.85), (1.0, 0.25, 0.25)),
    ("BoxTruck", (7.20, 2.40, 3.30), (0.75, 0.45, 1.0)),
    ("SchoolBus", (11.00, 2.50, 3.10), (1.0, 0.95, 0.2)),
)


def _default_classes():
    return {name: ClassSettings(list(size), list(rgb)) for name, size, rgb in _CLASSES}


@dataclasses.dataclass(frozen=True)
class LabellingConfig:
    classes: typing.Dict[str, ClassSettings] = bounded(factory=_default_classes)
    save_debounce: float = bounded(1.0, at_least=0.0)  # s after the last change of a frame
    min_size: float = bounded(0.1, above=0.0)  # m: no face drag makes a box thinner
    handles: HandleSettings = dataclasses.field(default_factory=HandleSettings)


def load_config(path=None):
    """The defaults, with the YAML file `path` laid over them; ConfigError names file and key."""
    config = LabellingConfig() if path is None else load_yaml_over(LabellingConfig(), path)
    where = path or "defaults"
    if not config.classes:
        raise ConfigError(f"{where}: classes: at least one class is needed")
    for name, settings in config.classes.items():
        for key, count in (("size", 3), ("colour", 3)):
            if len(getattr(settings, key)) != count:
                raise ConfigError(f"{where}: classes.{name}.{key}: expected {count} numbers, got "
                                  f"{getattr(settings, key)}")
        if not name.strip():
            raise ConfigError(f"{where}: classes: a class name must not be blank")
    return config
