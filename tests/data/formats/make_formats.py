#!/usr/bin/python3
"""Writes the small volume files tests/renderers/volume/format_readers_test.cpp reads, each with
a tool independent of svr: NIfTI with nibabel, DICOM with pydicom, TIFF pages with Pillow joined
by libtiff's tiffcp, and the same voxels as NRRD written here by hand (the test compares the two).

The grid is 5 × 4 × 3 int16, voxel (i, j, k) = i + 10 j + 100 k − 50, so a voxel's value says
where it was. Run from anywhere: /usr/bin/python3 make_formats.py [STEP…] (needs python3-nibabel,
python3-pydicom, python3-pil and libtiff-tools). The files are committed; this says how they came
to be, and makes them again.
"""
import os
import shutil
import subprocess
import sys

import nibabel
import numpy as np
import pydicom
from pydicom.dataset import Dataset, FileDataset, FileMetaDataset
from pydicom.sequence import Sequence
from pydicom.uid import (ExplicitVRBigEndian, ExplicitVRLittleEndian, ImplicitVRLittleEndian,
                         RLELossless, generate_uid)
from PIL import Image

NX, NY, NZ = 5, 4, 3
i, j, k = np.meshgrid(np.arange(NX), np.arange(NY), np.arange(NZ), indexing="ij")
GRID = (i + 10 * j + 100 * k - 50).astype(np.int16)  # indexed [i, j, k]


def nrrd(name, array, spacing, kind="short"):
    """array indexed [i, j, k]; written x fastest."""
    dtype = {"short": "<i2", "ushort": "<u2", "float": "<f4"}[kind]
    body = np.ascontiguousarray(array.transpose(2, 1, 0)).astype(dtype)
    header = ("NRRD0004\n# made by make_formats.py\n"
              f"type: {kind}\ndimension: 3\nsizes: {' '.join(map(str, array.shape))}\n"
              f"spacings: {' '.join(map(str, spacing))}\nendian: little\nencoding: raw\n\n")
    with open(name, "wb") as f:
        f.write(header.encode() + body.tobytes())


def nifti():
    spacing = (0.5, 0.75, 1.25)
    # RAS-ordered grid: file axes already point R, A, S.
    img = nibabel.Nifti1Image(GRID, np.diag([*spacing, 1.0]))
    img.set_sform(np.diag([*spacing, 1.0]), code=1)
    nibabel.save(img, "ras.nii")
    nrrd("ras.nrrd", GRID, spacing)
    # The same voxels stored LPS (i towards L, j towards P) and as NIfTI-2, gzip-compressed.
    affine = np.diag([-spacing[0], -spacing[1], spacing[2], 1.0])
    img = nibabel.Nifti2Image(GRID[::-1, ::-1, :].copy(), affine)
    img.set_sform(affine, code=1)
    nibabel.save(img, "lps.nii.gz")
    # Axes permuted: file i runs along S, j along R, k along A; with scl_slope 2 and scl_inter −10.
    permuted = GRID.transpose(2, 0, 1).copy()  # [k, i, j]
    affine = np.zeros((4, 4))
    affine[2, 0], affine[0, 1], affine[1, 2], affine[3, 3] = spacing[2], spacing[0], spacing[1], 1
    img = nibabel.Nifti1Image(permuted, affine)
    img.set_qform(affine, code=1)
    img.set_sform(None, code=0)
    img.header.set_slope_inter(2.0, -10.0)
    nibabel.save(img, "ski_scaled.nii")
    nrrd("scaled.nrrd", 2.0 * GRID.astype(np.float32) - 10.0, spacing, kind="float")


def dicom_slice(folder, name, z, series, pixels, position=None, intercept=-1024.0,
                syntax=ExplicitVRLittleEndian, sequence=None):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"  # CT Image Storage
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian if syntax == RLELossless else syntax
    ds = FileDataset(name, {}, file_meta=meta, preamble=b"\0" * 128)
    ds.SOPClassUID = meta.MediaStorageSOPClassUID
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.Modality = "CT"
    ds.SeriesInstanceUID = series
    ds.StudyInstanceUID = "1.2.826.0.1.3680043.8.498.1"
    ds.ImageOrientationPatient = [1, 0, 0, 0, 1, 0]
    ds.ImagePositionPatient = position or [-10.0, -20.0, 2.5 * z]
    ds.PixelSpacing = [0.75, 0.5]  # between rows (y), between columns (x)
    ds.SliceThickness = 2.5
    ds.Rows, ds.Columns = pixels.shape
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.BitsAllocated = ds.BitsStored = 16
    ds.HighBit = 15
    ds.PixelRepresentation = 1
    ds.RescaleSlope = 1
    ds.RescaleIntercept = intercept
    if sequence is not None:
        ds.ReferencedImageSequence = sequence
    ds.is_little_endian = syntax != ExplicitVRBigEndian
    ds.is_implicit_VR = syntax == ImplicitVRLittleEndian
    if syntax == RLELossless:
        ds.compress(RLELossless, pixels.astype("<i2"))  # encapsulated: items, then a delimiter
    else:
        ds.PixelData = pixels.astype(">i2" if syntax == ExplicitVRBigEndian else "<i2").tobytes()
    ds.save_as(os.path.join(folder, name), write_like_original=False)


def referenced_images():
    """A sequence of undefined length whose second item holds a nested sequence: items of
    defined and undefined length, delimiters."""
    items = []
    for n in range(2):
        item = Dataset()
        item.ReferencedSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"
        item.ReferencedSOPInstanceUID = f"1.2.826.0.1.3680043.8.498.3.{n}"
        items.append(item)
    inner = Dataset()
    inner.CodeValue, inner.CodingSchemeDesignator, inner.CodeMeaning = "121311", "DCM", "Localizer"
    items[1].PurposeOfReferenceCodeSequence = Sequence([inner])
    outer = Sequence(items)
    outer.is_undefined_length = True
    return outer


def dicom_framings():
    """The series again in the other framings a reader meets: implicit VR (with sequences),
    explicit VR big endian, and RLE-compressed pixels (encapsulated pixel data)."""
    series = "1.2.826.0.1.3680043.8.498.4"
    stored = GRID + 1024
    for name, syntax in [("series_implicit", ImplicitVRLittleEndian),
                         ("series_big_endian", ExplicitVRBigEndian), ("series_rle", RLELossless)]:
        shutil.rmtree(name, ignore_errors=True)
        os.makedirs(name)
        for z in range(NZ):
            dicom_slice(name, f"IM{z:04d}.dcm", z, series, stored[:, :, z].T, syntax=syntax,
                        sequence=referenced_images())


def dicom():
    series = "1.2.826.0.1.3680043.8.498.2"
    stored = GRID + 1024  # the modality values are GRID once the intercept −1024 applies
    # series: good (the names run against the slices' order: the reader must sort by position);
    # mixed: its last file from another series; gap: slice 2 where 4 would be; tilt: slices
    # drifting sideways.
    for name in ["series", "mixed", "gap", "tilt"]:
        shutil.rmtree(name, ignore_errors=True)
        os.makedirs(name)
    for z in range(NZ):
        pixels = stored[:, :, z].T  # rows = j, columns = i
        dicom_slice("series", f"IM{NZ - z:04d}.dcm", z, series, pixels)
        dicom_slice("mixed", f"IM{z:04d}.dcm", z, series if z < 2 else series + ".9", pixels)
        dicom_slice("gap", f"IM{z:04d}.dcm", 2 * z if z == 2 else z, series, pixels)
        dicom_slice("tilt", f"IM{z:04d}.dcm", z, series, pixels, [-10.0, -20.0 + 1.0 * z, 2.5 * z])
    # The rows run along +x of DICOM's LPS frame (towards L), the columns along +y (towards P),
    # so in RAS the grid runs backwards along x and y.
    nrrd("series.nrrd", GRID[::-1, ::-1, :].astype(np.float32), (0.5, 0.75, 2.5), kind="float")


def tiff():
    pages = []
    for z in range(NZ):
        name = f"page{z}.tif"
        Image.fromarray(GRID[:, :, z].T.astype(np.uint16) + 50, mode="I;16").save(name)
        pages.append(name)
    subprocess.run(["tiffcp", "-c", "lzw", *pages, "stack.tif"], check=True)
    # The same pages in 16 × 16 tiles: the tiled path, and a tile larger than the page.
    subprocess.run(["tiffcp", "-t", "-w", "16", "-l", "16", "stack.tif", "stack_tiled.tif"],
                   check=True)
    shutil.rmtree("numbered", ignore_errors=True)
    os.makedirs("numbered")
    for z, page in enumerate(pages):
        os.replace(page, os.path.join("numbered", f"slice_{z + 7:03d}.tif"))
    Image.fromarray((GRID[:, :, 0].T / 8.0).astype(np.float32), mode="F").save("float.tif")
    nrrd("stack.nrrd", GRID + 50, (1, 1, 1), kind="ushort")


os.chdir(os.path.dirname(os.path.abspath(__file__)))
# Any of the steps may be named (make_formats.py dicom_framings); all by default.
for step in sys.argv[1:] or ["nifti", "dicom", "dicom_framings", "tiff"]:
    globals()[step]()
