"""Reading bags with errors that name the bag: rosbag raises its own types, genpy's, struct's
and UnicodeDecodeError (a file that is not a bag at all) for what users meet."""
import struct

import genpy
import rosbag


class BagError(ValueError):
    """A bag that cannot be read or converted; the message names the bag and what is wrong."""


# What reading a cut-short, corrupt or foreign file raises.
READ_ERRORS = (rosbag.ROSBagException, genpy.DeserializationError, struct.error,
               UnicodeDecodeError)


def open_bag(bag_path):
    """The bag, or a BagError that names it and says what is wrong."""
    try:
        return rosbag.Bag(bag_path)
    except rosbag.ROSBagUnindexedException as error:
        raise BagError(f"{bag_path}: the bag has no index (was its recording cut short?); "
                       f"'rosbag reindex {bag_path}' may repair it") from error
    except OSError as error:
        raise BagError(f"{bag_path}: cannot read bag: {error.strerror or error}") from error
    except READ_ERRORS as error:
        raise BagError(f"{bag_path}: not a readable bag: {error}") from error
