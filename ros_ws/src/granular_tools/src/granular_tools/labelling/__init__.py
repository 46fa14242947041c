"""The cuboid labelling tool (label_cuboids, kitti_labels): docs/labelling.md."""
