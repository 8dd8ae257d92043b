// PLUS toolkit readers: MetaImage sequences (.mha LOCAL, .mhd + raw, zlib-compressed, 8/16-bit,
// per-frame fields) and device-set XML (transforms, transform chains, clip rectangle and fan),
// on small synthetic files written here, their malformed variants (each an InputError naming the
// field), and the real recording in ../shared/data/plus (skipped when absent).
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "io/input_error.h"
#include "io/meta_image.h"
#include "io/plus_device_set.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

const fs::path kPlusData = fs::path(XSECT_SOURCE_DIR) / "../shared/data/plus";

/// A fresh temporary folder, removed with the object.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "xsect-plus-io-XXXXXX").string();
    if (!::mkdtemp(t.data())) throw std::runtime_error("mkdtemp failed");
    path = t;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name, const std::string& bytes) const {
    const fs::path p = path / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p.string();
  }
};

/// The InputError `f` throws (fails the test when it throws nothing or something else).
InputError inputError(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected an InputError, got: " << e.what();
    return InputError("", "", "wrong exception");
  }
  ADD_FAILURE() << "expected an InputError, nothing was thrown";
  return InputError("", "", "nothing thrown");
}

/// Reads every frame of the header at `path`.
std::vector<cv::Mat> readAll(const std::string& path) {
  const MetaImageHeader h = readMetaImageHeader(path);
  MetaImageFrames frames(h);
  std::vector<cv::Mat> out;
  for (int f = 0; f < h.frames; ++f) out.push_back(frames.next());
  return out;
}

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

std::string zlibCompress(const std::string& raw) {
  uLongf n = compressBound(uLong(raw.size()));
  std::string out(n, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(raw.data()),
                      uLong(raw.size()), 6),
            Z_OK);
  out.resize(n);
  return out;
}

/// 8-bit frames whose pixels are f*100 + y*10 + x.
std::vector<cv::Mat> frames8(int w, int h, int n) {
  std::vector<cv::Mat> v;
  for (int f = 0; f < n; ++f) {
    cv::Mat m(h, w, CV_8UC1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) m.at<std::uint8_t>(y, x) = std::uint8_t(f * 100 + y * 10 + x);
    v.push_back(m);
  }
  return v;
}

/// 16-bit frames of poorly compressible values (a hash of the position).
std::vector<cv::Mat> frames16(int w, int h, int n) {
  std::vector<cv::Mat> v;
  for (int f = 0; f < n; ++f) {
    cv::Mat m(h, w, CV_16UC1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        std::uint32_t k = std::uint32_t(f * 1000003 + y * 7919 + x);
        k ^= k >> 13;
        k *= 0x5bd1e995u;
        k ^= k >> 15;
        m.at<std::uint16_t>(y, x) = std::uint16_t(k);
      }
    v.push_back(m);
  }
  return v;
}

/// The frames' samples as stored: 16-bit little- or big-endian.
std::string bytesOf(const std::vector<cv::Mat>& frames, bool msb) {
  std::string s;
  for (const auto& m : frames)
    for (int y = 0; y < m.rows; ++y)
      for (int x = 0; x < m.cols; ++x) {
        if (m.type() == CV_8UC1) {
          s.push_back(char(m.at<std::uint8_t>(y, x)));
          continue;
        }
        const std::uint16_t v = m.at<std::uint16_t>(y, x);
        const char hi = char(v >> 8), lo = char(v & 0xff);
        s.push_back(msb ? hi : lo);
        s.push_back(msb ? lo : hi);
      }
  return s;
}

const char* kProbe0 = "1 0 0 10  0 0.8 -0.6 20  0 0.6 0.8 30  0 0 0 1";
const char* kProbe1 = "0 -1 0 -5 1 0 0 2.5 0 0 1 7 0 0 0 1";

/// A 2-frame 8-bit .mha header with PLUS per-frame fields, up to (excluding) ElementDataFile.
std::string plusHeader8(int w, int h, int n, const std::string& extra = "") {
  std::ostringstream s;
  s << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
    << "CompressedData = False\nDimSize = " << w << " " << h << " " << n << "\n"
    << "ElementSpacing = 1 1 1\nElementType = MET_UCHAR\nUltrasoundImageOrientation = UFA\n"
    << "Seq_Frame0000_ProbeToTrackerTransform = " << kProbe0 << "\n"
    << "Seq_Frame0000_ProbeToTrackerTransformStatus = OK\n"
    << "Seq_Frame0000_ReferenceToTrackerTransform = 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
    << "Seq_Frame0000_Timestamp = 12.5\nSeq_Frame0000_ImageStatus = OK\n"
    << "Seq_Frame0001_ProbeToTrackerTransform = " << kProbe1 << "\n"
    << "Seq_Frame0001_ProbeToTrackerTransformStatus = INVALID\n"
    << "Seq_Frame0001_Timestamp = 12.6\n"
    << extra;
  return s.str();
}

}  // namespace

// --------------------------------------------------------------------------------------------
// MetaImage

TEST(PlusIo, UncompressedEightBitMhaReadsBackPixelExact) {
  TempDir dir;
  const auto frames = frames8(5, 3, 2);
  const std::string head = plusHeader8(5, 3, 2) + "ElementDataFile = LOCAL\n";
  const std::string path = dir.file("seq.igs.mha", head + bytesOf(frames, false));

  const MetaImageHeader h = readMetaImageHeader(path);
  EXPECT_EQ(h.width, 5);
  EXPECT_EQ(h.height, 3);
  EXPECT_EQ(h.frames, 2);
  EXPECT_EQ(h.pixel, MetaPixelType::uint8);
  EXPECT_FALSE(h.compressed);
  EXPECT_TRUE(h.data_file.empty());
  EXPECT_EQ(h.data_offset, std::int64_t(head.size()));
  EXPECT_EQ(h.orientation, "UFA");
  EXPECT_TRUE(h.flip_columns);
  EXPECT_FALSE(h.flip_rows);
  EXPECT_EQ(h.field("ElementSpacing"), "1 1 1");
  EXPECT_EQ(h.line("ElementType"), 8);
  EXPECT_EQ(h.line("NoSuchKey"), -1);

  MetaImageFrames reader(h);
  EXPECT_EQ(reader.frames(), 2);
  for (int f = 0; f < 2; ++f) {
    EXPECT_EQ(reader.index(), f);
    EXPECT_TRUE(same(reader.next(), frames[f])) << "frame " << f;
  }
  EXPECT_THROW(reader.next(), std::out_of_range);

  // Per-frame fields.
  EXPECT_EQ(frameFieldKey(12, "Timestamp"), "Seq_Frame0012_Timestamp");
  EXPECT_EQ(frameField(h, 0, "ImageStatus").value_or(""), "OK");
  EXPECT_FALSE(frameField(h, 1, "ImageStatus"));
  const auto m0 = frameMatrix(h, 0, "ProbeToTrackerTransform");
  ASSERT_TRUE(m0);
  Mat4 expect;
  expect << 1, 0, 0, 10, 0, 0.8, -0.6, 20, 0, 0.6, 0.8, 30, 0, 0, 0, 1;
  EXPECT_EQ(*m0, expect);
  EXPECT_FALSE(frameMatrix(h, 1, "ReferenceToTrackerTransform"));
  EXPECT_TRUE(frameStatusOk(h, 0, "ProbeToTrackerTransformStatus"));
  EXPECT_FALSE(frameStatusOk(h, 1, "ProbeToTrackerTransformStatus"));
  EXPECT_TRUE(frameStatusOk(h, 0, "ReferenceToTrackerTransformStatus"));  // absent: OK
  EXPECT_DOUBLE_EQ(frameNumber(h, 1, "Timestamp").value_or(-1), 12.6);
  EXPECT_EQ(frameTransformNames(h),
            (std::vector<std::string>{"ProbeToTrackerTransform", "ReferenceToTrackerTransform"}));
}

TEST(PlusIo, CompressedSixteenBitMhaStreamsPixelExact) {
  TempDir dir;
  // 600 x 500 x 3 16-bit frames of poorly compressible values: the compressed stream spans
  // several 256 KiB chunks and frames end in the middle of chunks.
  const auto frames = frames16(600, 500, 3);
  const std::string z = zlibCompress(bytesOf(frames, false));
  ASSERT_GT(z.size(), std::size_t(1) << 19);
  const std::string head = "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
                           "CompressedData = True\nCompressedDataSize = " + std::to_string(z.size()) +
                           "\nDimSize = 600 500 3\nElementType = MET_USHORT\nElementDataFile = LOCAL\n";
  const std::string path = dir.file("seq16.mha", head + z);
  const MetaImageHeader h = readMetaImageHeader(path);
  EXPECT_TRUE(h.compressed);
  EXPECT_EQ(h.compressed_size, std::int64_t(z.size()));
  EXPECT_EQ(h.pixel, MetaPixelType::uint16);
  const auto got = readAll(path);
  ASSERT_EQ(got.size(), 3u);
  for (int f = 0; f < 3; ++f) EXPECT_TRUE(same(got[f], frames[f])) << "frame " << f;

  // Without CompressedDataSize the stream runs to the end of the file.
  std::string noSize = head;
  noSize.erase(noSize.find("CompressedDataSize"), noSize.find("DimSize") - noSize.find("CompressedDataSize"));
  const auto got2 = readAll(dir.file("seq16b.mha", noSize + z));
  for (int f = 0; f < 3; ++f) EXPECT_TRUE(same(got2[f], frames[f])) << "frame " << f;
}

TEST(PlusIo, MhdWithSeparateBigEndianRawFile) {
  TempDir dir;
  const auto frames = frames16(9, 4, 2);
  fs::create_directories(dir.path / "data");
  dir.file("data/pixels.raw", std::string(16, 'x') + bytesOf(frames, true));  // HeaderSize 16
  const std::string path = dir.file(
      "seq.mhd", "NDims = 3\nDimSize = 9 4 2\nElementType = MET_USHORT\nElementByteOrderMSB = True\n"
                 "HeaderSize = 16\nElementDataFile = data/pixels.raw\n");
  const MetaImageHeader h = readMetaImageHeader(path);
  EXPECT_TRUE(h.msb);
  EXPECT_EQ(fs::path(h.data_file), dir.path / "data/pixels.raw");
  EXPECT_EQ(h.data_offset, 16);
  const auto got = readAll(path);
  for (int f = 0; f < 2; ++f) EXPECT_TRUE(same(got[f], frames[f])) << "frame " << f;

  // A 2D image: NDims 2, one frame; HeaderSize -1: the data is the end of the file.
  dir.file("one.raw", "garbage" + bytesOf({frames[1]}, true));
  const std::string one = dir.file("one.mhd", "NDims = 2\nDimSize = 9 4\nElementType = MET_USHORT\n"
                                              "BinaryDataByteOrderMSB = True\nHeaderSize = -1\nElementDataFile = one.raw\n");
  const auto got1 = readAll(one);
  ASSERT_EQ(got1.size(), 1u);
  EXPECT_TRUE(same(got1[0], frames[1]));
}

TEST(PlusIo, MalformedHeadersNameTheirField) {
  TempDir dir;
  const std::string px(2 * 3 * 2, '\x07');
  const auto err = [&](const std::string& name, const std::string& header, const std::string& data) {
    const std::string p = dir.file(name, header + data);
    return inputError([&] { readAll(p); });
  };
  const std::string ok = "NDims = 3\nDimSize = 2 3 2\nElementType = MET_UCHAR\n";
  EXPECT_NO_THROW(readAll(dir.file("ok.mha", ok + "ElementDataFile = LOCAL\n" + px)));

  auto e = err("nodim.mha", "NDims = 3\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.field(), "DimSize") << e.what();

  e = err("ndims.mha", "NDims = 3\nDimSize = 2 3\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.field(), "DimSize") << e.what();
  EXPECT_EQ(e.line(), 2);

  e = err("zero.mha", "NDims = 3\nDimSize = 2 0 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.field(), "DimSize") << e.what();

  e = err("huge.mha", "NDims = 3\nDimSize = 2000000000 2000000000 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.field(), "DimSize") << e.what();

  e = err("type.mha", "NDims = 3\nDimSize = 2 3 2\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.field(), "ElementType") << e.what();
  EXPECT_NE(std::string(e.what()).find("MET_FLOAT"), std::string::npos);
  EXPECT_EQ(e.line(), 3);

  e = err("rgb.mha", ok + "ElementNumberOfChannels = 3\nElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.field(), "ElementNumberOfChannels") << e.what();

  e = err("comp.mha", ok + "CompressedData = Maybe\nElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.field(), "CompressedData") << e.what();

  e = err("orient.mha", ok + "UltrasoundImageOrientation = AMF\nElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.field(), "UltrasoundImageOrientation") << e.what();

  e = err("nodata.mha", ok, "");
  EXPECT_EQ(e.field(), "ElementDataFile") << e.what();

  e = err("short.mha", ok + "ElementDataFile = LOCAL\n", px.substr(1));
  EXPECT_EQ(e.field(), "ElementDataFile") << e.what();
  EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();

  e = err("missing.mhd", ok + "ElementDataFile = nowhere.raw\n", "");
  EXPECT_EQ(e.field(), "ElementDataFile") << e.what();

  e = err("list.mhd", ok + "ElementDataFile = LIST\n", "");
  EXPECT_EQ(e.field(), "ElementDataFile") << e.what();

  e = err("noeq.mha", "NDims 3\n" + ok + "ElementDataFile = LOCAL\n", px);
  EXPECT_EQ(e.line(), 1) << e.what();
}

TEST(PlusIo, CorruptOrTruncatedCompressedDataIsAnInputError) {
  TempDir dir;
  const auto frames = frames16(300, 200, 4);
  const std::string z = zlibCompress(bytesOf(frames, false));
  const std::string headNoSize = "NDims = 3\nDimSize = 300 200 4\nElementType = MET_USHORT\nCompressedData = True\n";
  const std::string local = "ElementDataFile = LOCAL\n";

  // Flipped bytes in the middle of the stream: a zlib data error or a checksum mismatch.
  std::string bad = z;
  for (std::size_t i = bad.size() / 2; i < bad.size() / 2 + 8; ++i) bad[i] = char(~bad[i]);
  auto e = inputError([&] { readAll(dir.file("corrupt.mha", headNoSize + local + bad)); });
  EXPECT_EQ(e.field(), "CompressedData") << e.what();
  EXPECT_NE(std::string(e.what()).find("corrupt"), std::string::npos) << e.what();

  // Cut in the middle, no CompressedDataSize: found while inflating, naming the frame.
  const std::string cut = z.substr(0, z.size() / 2);
  e = inputError([&] { readAll(dir.file("cut.mha", headNoSize + local + cut)); });
  EXPECT_EQ(e.field(), "CompressedData") << e.what();
  EXPECT_NE(std::string(e.what()).find("truncated at frame"), std::string::npos) << e.what();

  // Cut with CompressedDataSize: found from the header, before any pixel is read.
  const std::string sized = headNoSize + "CompressedDataSize = " + std::to_string(z.size()) + "\n" + local;
  e = inputError([&] { readMetaImageHeader(dir.file("cutsized.mha", sized + cut)); });
  EXPECT_EQ(e.field(), "CompressedDataSize") << e.what();

  // The stream's last bytes (its checksum) missing.
  e = inputError([&] { readAll(dir.file("nocheck.mha", headNoSize + local + z.substr(0, z.size() - 2))); });
  EXPECT_EQ(e.field(), "CompressedData") << e.what();

  // Not a zlib stream at all.
  e = inputError([&] { readAll(dir.file("garbage.mha", headNoSize + local + std::string(5000, 'g'))); });
  EXPECT_EQ(e.field(), "CompressedData") << e.what();
}

TEST(PlusIo, MalformedFrameMatrixNamesTheField) {
  TempDir dir;
  const auto frames = frames8(2, 2, 2);
  const std::string extra = "Seq_Frame0001_ReferenceToTrackerTransform = 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0\n"
                            "Seq_Frame0000_StylusToTrackerTransform = 1 0 0 abc 0 1 0 0 0 0 1 0 0 0 0 1\n"
                            "Seq_Frame0001_Timestamp2 = soon\n";
  const std::string path = dir.file("m.mha", plusHeader8(2, 2, 2, extra) + "ElementDataFile = LOCAL\n" +
                                                 bytesOf(frames, false));
  const MetaImageHeader h = readMetaImageHeader(path);
  auto e = inputError([&] { frameMatrix(h, 0, "StylusToTrackerTransform"); });
  EXPECT_EQ(e.field(), "Seq_Frame0000_StylusToTrackerTransform") << e.what();
  EXPECT_EQ(e.line(), h.line("Seq_Frame0000_StylusToTrackerTransform"));
  EXPECT_NE(std::string(e.what()).find("abc"), std::string::npos);
  e = inputError([&] { frameMatrix(h, 1, "ReferenceToTrackerTransform"); });
  EXPECT_EQ(e.field(), "Seq_Frame0001_ReferenceToTrackerTransform") << e.what();
  e = inputError([&] { frameNumber(h, 1, "Timestamp2"); });
  EXPECT_EQ(e.field(), "Seq_Frame0001_Timestamp2") << e.what();
  EXPECT_EQ(frameTransformNames(h),
            (std::vector<std::string>{"ProbeToTrackerTransform", "ReferenceToTrackerTransform",
                                      "StylusToTrackerTransform"}));
}

// --------------------------------------------------------------------------------------------
// Device set

namespace {

const char* kDeviceSet = R"(<?xml version="1.0"?>
<PlusConfiguration version="2.1">
  <DataCollection>
    <Device Id="VolumeReconstructorDevice" Type="VirtualVolumeReconstructor">
      <VolumeReconstruction ImageCoordinateFrame="Image" ReferenceCoordinateFrame="Reference"
        ClipRectangleOrigin="10 20" ClipRectangleSize="60 50"
        FanAnglesDeg="30 -30" FanOriginPixel="40 5" FanRadiusStartPixel="20" FanRadiusStopPixel="60"
        OutputSpacing="0.5 0.5 0.5" />
    </Device>
  </DataCollection>
  <CoordinateDefinitions>
    <Transform From="Image" To="Probe"
      Matrix="0     0.08    0     11
              -0.08 0       0     50
              0     0       0.08  0
              0     0       0     1" />
    <Transform From="Phantom" To="Reference" Matrix="0 -1 0 5  1 0 0 -3  0 0 1 9  0 0 0 1" />
  </CoordinateDefinitions>
</PlusConfiguration>
)";

Mat4 rigid(double angleRad, const Vec3& axis, const Vec3& t) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angleRad, axis.normalized()).toRotationMatrix();
  m.topRightCorner<3, 1>() = t;
  return m;
}

}  // namespace

TEST(PlusIo, DeviceSetTransformsChainsAndFieldOfView) {
  TempDir dir;
  const PlusDeviceSet ds = readPlusDeviceSet(dir.file("set.xml", kDeviceSet));
  ASSERT_EQ(ds.transforms.size(), 2u);
  EXPECT_EQ(ds.transforms[0].from, "Image");
  EXPECT_EQ(ds.transforms[0].to, "Probe");
  Mat4 imageToProbe;
  imageToProbe << 0, 0.08, 0, 11, -0.08, 0, 0, 50, 0, 0, 0.08, 0, 0, 0, 0, 1;
  EXPECT_EQ(ds.transforms[0].matrix, imageToProbe);
  Mat4 phantomToReference;
  phantomToReference << 0, -1, 0, 5, 1, 0, 0, -3, 0, 0, 1, 9, 0, 0, 0, 1;
  EXPECT_EQ(ds.transforms[1].matrix, phantomToReference);
  EXPECT_EQ(ds.image_frame, "Image");
  EXPECT_EQ(ds.reference_frame, "Reference");
  ASSERT_TRUE(ds.clip_origin && ds.clip_size);
  EXPECT_EQ(*ds.clip_origin, (std::array<int, 2>{10, 20}));
  EXPECT_EQ(*ds.clip_size, (std::array<int, 2>{60, 50}));
  ASSERT_TRUE(ds.fan);
  EXPECT_EQ(ds.fan->angles_deg, (std::array<double, 2>{-30, 30}));  // sorted
  EXPECT_EQ(ds.fan->origin_px, (std::array<double, 2>{40, 5}));
  EXPECT_EQ(ds.fan->radius_start_px, 20);
  EXPECT_EQ(ds.fan->radius_stop_px, 60);

  // ImageToReference = inverse(ReferenceToTracker) * ProbeToTracker * ImageToProbe.
  const Mat4 probeToTracker = rigid(0.7, {1, 2, 3}, {-190, -98, -1949});
  const Mat4 referenceToTracker = rigid(-1.2, {0, 1, 0.3}, {-208, -115, -1992});
  std::vector<PlusTransform> all = ds.transforms;
  all.push_back({"Probe", "Tracker", probeToTracker});
  all.push_back({"Reference", "Tracker", referenceToTracker});
  const Mat4 imageToReference = referenceToTracker.inverse() * probeToTracker * imageToProbe;
  const auto chained = chainTransform(all, "Image", "Reference");
  ASSERT_TRUE(chained);
  EXPECT_TRUE(chained->isApprox(imageToReference, 1e-12)) << *chained << "\n\n" << imageToReference;
  const auto toPhantom = chainTransform(all, "Image", "Phantom");
  ASSERT_TRUE(toPhantom);
  EXPECT_TRUE(toPhantom->isApprox(phantomToReference.inverse() * imageToReference, 1e-12));
  const auto back = chainTransform(all, "Reference", "Image");
  ASSERT_TRUE(back);
  EXPECT_LT(((*back * imageToReference) - Mat4::Identity()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_FALSE(chainTransform(all, "Image", "Stylus"));
  EXPECT_FALSE(chainTransform(ds.transforms, "Image", "Reference"));  // no tracking: no chain
  EXPECT_EQ(*chainTransform({}, "Image", "Image"), Mat4::Identity());

  // The shortest chain wins.
  const Mat4 direct = rigid(0.3, {0, 0, 1}, {1, 2, 3});
  all.push_back({"Image", "Tracker", direct});
  EXPECT_TRUE(chainTransform(all, "Image", "Tracker")->isApprox(direct));

  // Field of view: the clip rectangle x 10..69, y 20..69, intersected with the fan (apex (40, 5),
  // edges at +-30 degrees from +y, radii 20..60).
  const cv::Mat fov = plusFieldOfView(ds, 100, 80);
  ASSERT_EQ(fov.type(), CV_8UC1);
  ASSERT_EQ(fov.size(), cv::Size(100, 80));
  EXPECT_EQ(fov.at<std::uint8_t>(40, 40), 255);  // below the apex, radius 35
  EXPECT_EQ(fov.at<std::uint8_t>(22, 40), 0);    // radius 17 < 20
  EXPECT_EQ(fov.at<std::uint8_t>(25, 55), 0);    // 36.9 degrees off the axis
  EXPECT_EQ(fov.at<std::uint8_t>(64, 40), 255);  // radius 59, inside the clip rectangle
  EXPECT_EQ(fov.at<std::uint8_t>(70, 40), 0);    // below the clip rectangle (and radius 65)
  PlusDeviceSet clipOnly = ds;
  clipOnly.fan.reset();
  const cv::Mat rect = plusFieldOfView(clipOnly, 100, 80);
  EXPECT_EQ(cv::countNonZero(rect), 60 * 50);
  EXPECT_EQ(rect.at<std::uint8_t>(20, 10), 255);
  EXPECT_EQ(rect.at<std::uint8_t>(69, 69), 255);
  EXPECT_EQ(rect.at<std::uint8_t>(70, 69), 0);
  EXPECT_EQ(cv::countNonZero(plusFieldOfView(clipOnly, 30, 30)), 20 * 10);  // cut by the frame
  clipOnly.clip_size = std::array<int, 2>{0, 0};
  EXPECT_TRUE(plusFieldOfView(clipOnly, 100, 80).empty());  // 0 0: the whole frame

  EXPECT_EQ(splitTransformName("ProbeToTrackerTransform"), std::make_pair(std::string("Probe"), std::string("Tracker")));
  EXPECT_EQ(splitTransformName("ToolToTracker"), std::make_pair(std::string("Tool"), std::string("Tracker")));
  EXPECT_FALSE(splitTransformName("Probe"));
  EXPECT_FALSE(splitTransformName("AToBToC"));
}

TEST(PlusIo, MalformedDeviceSetsNameTheirField) {
  TempDir dir;
  const auto err = [&](const std::string& name, const std::string& xml) {
    const std::string p = dir.file(name, xml);
    return inputError([&] { readPlusDeviceSet(p); });
  };
  const auto wrap = [](const std::string& inner) {
    return "<PlusConfiguration>\n<CoordinateDefinitions>\n" + inner + "\n</CoordinateDefinitions>\n</PlusConfiguration>\n";
  };
  const std::string id = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1";
  EXPECT_NO_THROW(readPlusDeviceSet(dir.file("ok.xml", wrap("<Transform From=\"Image\" To=\"Probe\" Matrix=\"" + id + "\"/>"))));
  EXPECT_NO_THROW(readPlusDeviceSet(dir.file("empty.xml", "<PlusConfiguration/>")));

  auto e = err("malformed.xml", "<PlusConfiguration>\n<CoordinateDefinitions>\n<Transform From=\"A\"\n</PlusConfiguration>\n");
  EXPECT_NE(std::string(e.what()).find("malformed XML"), std::string::npos) << e.what();
  EXPECT_GE(e.line(), 3) << e.what();

  e = err("root.xml", "<Configuration/>");
  EXPECT_EQ(e.field(), "PlusConfiguration") << e.what();

  const std::string field = "CoordinateDefinitions/Transform[From=Image,To=Probe].Matrix";
  e = err("nomatrix.xml", wrap("<Transform From=\"Image\" To=\"Probe\" />"));
  EXPECT_EQ(e.field(), field) << e.what();
  EXPECT_EQ(e.line(), 3);

  e = err("nofrom.xml", wrap("<Transform To=\"Probe\" Matrix=\"" + id + "\"/>"));
  EXPECT_EQ(e.field(), "CoordinateDefinitions/Transform[1].From") << e.what();

  e = err("fifteen.xml", wrap("<Transform From=\"Image\" To=\"Probe\" Matrix=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0\"/>"));
  EXPECT_EQ(e.field(), field) << e.what();

  e = err("nan.xml", wrap("<Transform From=\"Image\" To=\"Probe\" Matrix=\"1 0 0 0 0 1 0 0 0 0 1 nan 0 0 0 1\"/>"));
  EXPECT_EQ(e.field(), field) << e.what();

  e = err("word.xml", wrap("<Transform From=\"Image\" To=\"Probe\" Matrix=\"1 0 0 0 0 1 0 0 0 0 1 x 0 0 0 1\"/>"));
  EXPECT_EQ(e.field(), field) << e.what();

  e = err("lastrow.xml", wrap("<Transform From=\"Image\" To=\"Probe\" Matrix=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1\"/>"));
  EXPECT_EQ(e.field(), field) << e.what();

  e = err("singular.xml", wrap("<Transform From=\"Image\" To=\"Probe\" Matrix=\"1 0 0 0 2 0 0 0 0 0 1 0 0 0 0 1\"/>"));
  EXPECT_EQ(e.field(), field) << e.what();
  EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos);

  e = err("twice.xml", wrap("<Transform From=\"Image\" To=\"Probe\" Matrix=\"" + id + "\"/>\n"
                            "<Transform From=\"Probe\" To=\"Image\" Matrix=\"" + id + "\"/>"));
  EXPECT_EQ(e.field(), "CoordinateDefinitions/Transform[From=Probe,To=Image]") << e.what();
  EXPECT_EQ(e.line(), 4);

  e = err("clip.xml", "<PlusConfiguration><VolumeReconstruction ClipRectangleSize=\"10 -3\"/></PlusConfiguration>");
  EXPECT_EQ(e.field(), "VolumeReconstruction.ClipRectangleSize") << e.what();

  e = err("fan.xml", "<PlusConfiguration><VolumeReconstruction FanAnglesDeg=\"-30 95\"/></PlusConfiguration>");
  EXPECT_EQ(e.field(), "VolumeReconstruction.FanAnglesDeg") << e.what();

  e = err("radius.xml", "<PlusConfiguration><VolumeReconstruction FanAngles=\"-30 30\" FanDepth=\"0\"/></PlusConfiguration>");
  EXPECT_EQ(e.field(), "VolumeReconstruction.FanDepth") << e.what();
}

// --------------------------------------------------------------------------------------------
// The real recording (PlusLibData): NwirePhantomFreehand.

TEST(PlusIo, RealNwirePhantomRecording) {
  const fs::path mha = kPlusData / "NwirePhantomFreehand.igs.mha";
  const fs::path xml = kPlusData / "PlusDeviceSet_NwirePhantomFreehand_vtkVolumeReconstructorTest2.xml";
  if (!fs::exists(mha) || !fs::exists(xml)) GTEST_SKIP() << "no " << kPlusData;

  const MetaImageHeader h = readMetaImageHeader(mha.string());
  EXPECT_EQ(h.width, 820);
  EXPECT_EQ(h.height, 616);
  EXPECT_EQ(h.frames, 97);
  EXPECT_EQ(h.pixel, MetaPixelType::uint8);
  EXPECT_TRUE(h.compressed);
  EXPECT_EQ(h.compressed_size, 547799);
  EXPECT_EQ(h.orientation, "MFA");
  EXPECT_FALSE(h.flip_columns);
  EXPECT_FALSE(h.flip_rows);
  EXPECT_EQ(frameTransformNames(h), (std::vector<std::string>{"ProbeToTrackerTransform", "ReferenceToTrackerTransform",
                                                               "StylusToTrackerTransform"}));
  Mat4 probe0;
  probe0 << 0.956683, -0.263308, 0.124204, -190.886, 0.269031, 0.962616, -0.0315089, -98.0911, -0.111264,
      0.0635588, 0.991756, -1949.07, 0, 0, 0, 1;
  EXPECT_EQ(frameMatrix(h, 0, "ProbeToTrackerTransform").value(), probe0);
  EXPECT_TRUE(frameStatusOk(h, 0, "ProbeToTrackerTransformStatus"));
  EXPECT_FALSE(frameStatusOk(h, 0, "StylusToTrackerTransformStatus"));
  EXPECT_DOUBLE_EQ(frameNumber(h, 0, "Timestamp").value(), 345.627957);
  EXPECT_DOUBLE_EQ(frameNumber(h, 96, "Timestamp").value(), 355.783014);

  const PlusDeviceSet ds = readPlusDeviceSet(xml.string());
  Mat4 imageToProbe;
  imageToProbe << -0.0094, -0.0739, -0.0028, -103.5322, 0.0774, -0.0076, -0.0049, -43.1227, 0.0046, -0.0032, 0.0760,
      -93.3, 0, 0, 0, 1;
  bool found = false;
  for (const auto& t : ds.transforms)
    if (t.from == "Image" && t.to == "Probe") {
      found = true;
      EXPECT_EQ(t.matrix, imageToProbe);
    }
  EXPECT_TRUE(found);
  ASSERT_TRUE(ds.clip_origin && ds.clip_size);
  EXPECT_EQ(*ds.clip_origin, (std::array<int, 2>{167, 62}));
  EXPECT_EQ(*ds.clip_size, (std::array<int, 2>{495, 488}));
  EXPECT_FALSE(ds.fan);
  EXPECT_EQ(cv::countNonZero(plusFieldOfView(ds, h.width, h.height)), 495 * 488);

  // Frame 0 ImageToReference through the recorded and calibrated transforms.
  std::vector<PlusTransform> all = ds.transforms;
  const Mat4 ref0 = frameMatrix(h, 0, "ReferenceToTrackerTransform").value();
  all.push_back({"Probe", "Tracker", probe0});
  all.push_back({"Reference", "Tracker", ref0});
  const auto imageToReference = chainTransform(all, "Image", "Reference");
  ASSERT_TRUE(imageToReference);
  EXPECT_TRUE(imageToReference->isApprox(ref0.inverse() * probe0 * imageToProbe, 1e-12));

  MetaImageFrames frames(h);
  for (int f = 0; f < h.frames; ++f) {
    const cv::Mat m = frames.next();
    ASSERT_EQ(m.size(), cv::Size(820, 616));
    ASSERT_EQ(m.type(), CV_8UC1);
    double lo = 0, hi = 0;
    cv::minMaxLoc(m, &lo, &hi);
    EXPECT_LT(lo, hi) << "frame " << f << " is constant";
  }
  EXPECT_EQ(frames.index(), 97);
}
