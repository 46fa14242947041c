"""Our lgsvl_msgs must match the LGSVL simulator's own package on the wire."""
import subprocess

import pytest
from lgsvl_msgs.msg import BoundingBox3D, Detection3D, Detection3DArray

# md5sums of the simulator's lgsvl_msgs, as `rosmsg md5` prints them there.
SIMULATOR_MD5SUMS = {
    "BoundingBox3D": "0afc39928ba33aad299a6acabb48fd7d",
    "Detection3D": "6818b3f7aceb08a7c1eaab8d7fea63e8",
    "Detection3DArray": "463b7bf1d7d2ef45e33f14d3ed064e13",
}


@pytest.mark.parametrize("message", [BoundingBox3D, Detection3D, Detection3DArray])
def test_generated_python_message_has_simulator_md5sum(message):
    assert message._md5sum == SIMULATOR_MD5SUMS[message.__name__]


@pytest.mark.parametrize("name", sorted(SIMULATOR_MD5SUMS))
def test_rosmsg_md5_prints_simulator_md5sum(name):
    printed = subprocess.run(["rosmsg", "md5", f"lgsvl_msgs/{name}"], check=True,
                             capture_output=True, text=True).stdout.strip()
    assert printed == SIMULATOR_MD5SUMS[name]
