"""Volume file writers shared by the tool tests (test_geom_iso_volumes.sh,
test_scene_volumes.sh): import it with sys.path set to tests/tools.

nifti(samples, spacing, origin, flip=False): a NIfTI-1 single file (.nii,
little-endian, 352-byte header, vox_offset 352) of a numpy array indexed
[z, y, x] (x fastest in the file), datatype and bitpix from its dtype,
pixdim = spacing, qform_code 0 and sform_code 1 with the sform's diagonal
= spacing and its offset = origin. flip=True stores x reversed under a
negative sform x axis (file x runs from +x to -x): the same world volume.
"""
import struct

import numpy as np

# NIfTI-1 datatype codes (nifti1.h)
DATATYPE = {'u1': 2, 'i2': 4, 'i4': 8, 'f4': 16, 'f8': 64, 'i1': 256, 'u2': 512, 'u4': 768}


def nifti(samples, spacing, origin, flip=False):
    a = np.asarray(samples)
    key = a.dtype.kind + str(a.dtype.itemsize)
    if key not in DATATYPE:
        raise ValueError('no NIfTI-1 datatype for %s' % a.dtype)
    nz, ny, nx = a.shape
    sp, org = spacing, origin
    h = bytearray(352)
    struct.pack_into('<i', h, 0, 348)
    struct.pack_into('<8h', h, 40, 3, nx, ny, nz, 1, 1, 1, 1)
    struct.pack_into('<hh', h, 70, DATATYPE[key], 8 * a.dtype.itemsize)
    struct.pack_into('<8f', h, 76, 1, sp[0], sp[1], sp[2], 1, 1, 1, 1)
    struct.pack_into('<f', h, 108, 352)
    struct.pack_into('<hh', h, 252, 0, 1)
    ox = org[0] + (nx - 1) * sp[0] if flip else org[0]
    struct.pack_into('<4f', h, 280, -sp[0] if flip else sp[0], 0, 0, ox)
    struct.pack_into('<4f', h, 296, 0, sp[1], 0, org[1])
    struct.pack_into('<4f', h, 312, 0, 0, sp[2], org[2])
    h[344:348] = b'n+1\0'
    data = a[:, :, ::-1] if flip else a
    return bytes(h) + data.astype(a.dtype.newbyteorder('<')).tobytes()
