from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["granular_tools", "granular_tools.simulation",
                                           "granular_tools.visualization",
                                           "granular_tools.bag_to_files",
                                           "granular_tools.models",
                                           "granular_tools.evaluation",
                                           "granular_tools.labelling",
                                           "granular_tools.online",
                                           "granular_tools.runners",
                                           "granular_tools.fleet"],
                                 package_dir={"": "src"}))
