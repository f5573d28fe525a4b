// Tests for solver/io: AtomicFile, CsvWriter, SnapshotSeries (HDF5 + XDMF).
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_writer.hpp"
#include "io/snapshot_writer.hpp"

namespace fs = std::filesystem;
using namespace sph;

namespace {

// A fresh directory per test, removed afterwards.
class IoTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("sph_test_io_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string p(const std::string& name) const { return (dir_ / name).string(); }

    fs::path dir_;
};

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Names of everything in `dir` that looks like a leftover temporary.
std::vector<std::string> temporaries(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos)
            out.push_back(e.path().string());
    return out;
}

std::size_t count(const std::string& text, const std::string& needle) {
    std::size_t k = 0;
    for (auto pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + 1)) ++k;
    return k;
}

SnapshotData make_snapshot(long step, double time, std::size_t n) {
    SnapshotData d;
    d.step = step;
    d.time = time;
    for (std::size_t i = 0; i < n; ++i) {
        const double s = static_cast<double>(step);
        d.position.insert(d.position.end(), {1.0 + 0.1 * i + s, 2.0 + 1e-12 * i, -3.0 - i});
        d.velocity.insert(d.velocity.end(), {0.5f * i, -0.25f, static_cast<float>(s)});
        d.density.push_back(1000.0f + i);
        d.pressure.push_back(-5.5f * i);
        d.type.push_back(static_cast<std::uint8_t>(i % 2));
        d.id.push_back(static_cast<std::uint32_t>(100 + i));
    }
    return d;
}

// Reads a whole dataset with the HDF5 C API, checking its shape and stored type class.
template <class T>
std::vector<T> read_dataset(hid_t file, const char* name, hid_t mem_type, H5T_class_t cls,
                            std::size_t type_size, std::vector<hsize_t> expect_dims) {
    hid_t d = H5Dopen2(file, name, H5P_DEFAULT);
    EXPECT_GE(d, 0) << name;
    hid_t s = H5Dget_space(d);
    const int rank = H5Sget_simple_extent_ndims(s);
    std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
    H5Sget_simple_extent_dims(s, dims.data(), nullptr);
    EXPECT_EQ(dims, expect_dims) << name;
    hid_t t = H5Dget_type(d);
    EXPECT_EQ(H5Tget_class(t), cls) << name;
    EXPECT_EQ(H5Tget_size(t), type_size) << name;
    std::size_t total = 1;
    for (hsize_t x : dims) total *= x;
    std::vector<T> out(total);
    if (total) {
        EXPECT_GE(H5Dread(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), 0);
    }
    H5Tclose(t);
    H5Sclose(s);
    H5Dclose(d);
    return out;
}

template <class T>
T read_attribute(hid_t file, const char* name, hid_t mem_type) {
    T value{};
    hid_t a = H5Aopen(file, name, H5P_DEFAULT);
    EXPECT_GE(a, 0) << name;
    EXPECT_GE(H5Aread(a, mem_type, &value), 0) << name;
    H5Aclose(a);
    return value;
}

}  // namespace

// ---- AtomicFile ------------------------------------------------------------------------

TEST_F(IoTest, AtomicFileNotCommittedLeavesNothing) {
    const std::string path = p("sub/dir/out.txt");
    {
        AtomicFile f(path);
        EXPECT_TRUE(fs::is_directory(dir_ / "sub/dir"));  // parents created up front
        f.stream() << "half written";
        EXPECT_TRUE(fs::exists(f.temp_path()));
        EXPECT_FALSE(fs::exists(path));
    }
    EXPECT_FALSE(fs::exists(path));
    EXPECT_TRUE(temporaries(dir_).empty());
}

TEST_F(IoTest, AtomicFileCommittedIsComplete) {
    const std::string path = p("out.txt");
    {
        AtomicFile f(path);
        f.stream() << "line 1\nline 2\n";
        f.commit();
        EXPECT_TRUE(f.committed());
        EXPECT_THROW(f.commit(), RunError);
    }
    EXPECT_EQ(slurp(path), "line 1\nline 2\n");
    EXPECT_TRUE(temporaries(dir_).empty());
}

TEST_F(IoTest, AtomicFileKeepsOldContentUntilCommit) {
    const std::string path = p("out.txt");
    std::ofstream(path) << "old";
    {
        AtomicFile f(path);
        f.stream() << "new";
        EXPECT_EQ(slurp(path), "old");
    }
    EXPECT_EQ(slurp(path), "old");  // abandoned rewrite: old file untouched
    {
        AtomicFile f(path);
        f.stream() << "new";
        f.commit();
    }
    EXPECT_EQ(slurp(path), "new");
}

TEST_F(IoTest, AtomicFileUnderRegularFileThrowsWithPath) {
    std::ofstream(p("blocker")) << "x";
    const std::string path = p("blocker/sub/out.txt");
    try {
        AtomicFile f(path);
        FAIL() << "expected RunError";
    } catch (const RunError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}

// ---- CsvWriter -------------------------------------------------------------------------

TEST_F(IoTest, CsvRoundTrip) {
    const std::string path = p("results/table.csv");
    {
        CsvWriter csv(path, {"time", "label", "value"},
                      {{"solver", "sph 0.1"}, {"command", "run --a=1\n--b"}});
        csv.row({CsvWriter::fmt(0.0), "plain", CsvWriter::fmt(0.1)});
        csv.row({CsvWriter::fmt(1.5), "a,b", CsvWriter::fmt(-2.5e-300)});
        csv.row({CsvWriter::fmt(3.0), "say \"hi\"", CsvWriter::fmt(1e21)});
        csv.row({CsvWriter::fmt(4.0), "two\nlines", "#7"});
        EXPECT_FALSE(fs::exists(path));  // nothing under the final name before commit
        csv.commit();
    }
    const std::string expected =
        "# solver: sph 0.1\n"
        "# command: run --a=1\\n--b\n"
        "time,label,value\n"
        "0,plain,0.1\n"
        "1.5,\"a,b\",-2.5e-300\n"
        "3,\"say \"\"hi\"\"\",1e+21\n"
        "4,\"two\nlines\",\"#7\"\n";
    EXPECT_EQ(slurp(path), expected);
    EXPECT_TRUE(temporaries(dir_).empty());
}

TEST_F(IoTest, CsvWrongCellCountThrows) {
    const std::string path = p("t.csv");
    CsvWriter csv(path, {"a", "b"});
    EXPECT_THROW(csv.row({"1"}), RunError);
    EXPECT_THROW(csv.row({"1", "2", "3"}), RunError);
    try {
        csv.row({});
        FAIL() << "expected RunError";
    } catch (const RunError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    csv.row({"1", "2"});
    csv.commit();
    EXPECT_EQ(slurp(path), "a,b\n1,2\n");
    EXPECT_THROW(csv.row({"1", "2"}), RunError);
}

TEST_F(IoTest, CsvUncommittedLeavesNothing) {
    {
        CsvWriter csv(p("t.csv"), {"a"});
        csv.row({"1"});
    }
    EXPECT_FALSE(fs::exists(p("t.csv")));
    EXPECT_TRUE(temporaries(dir_).empty());
}

TEST(CsvFmt, ShortestRoundTrip) {
    EXPECT_EQ(CsvWriter::fmt(0.1), "0.1");
    EXPECT_EQ(CsvWriter::fmt(1.0), "1");
    EXPECT_EQ(CsvWriter::fmt(-0.0), "-0");
    EXPECT_EQ(CsvWriter::fmt(INFINITY), "inf");
    for (double v : {0.1, 1.0 / 3.0, 2.0 / 3.0, 1e300, 5e-324, -123456.789, 6.02214076e23,
                     0.30000000000000004}) {
        // strtod, not stod: stod throws on subnormals such as 5e-324.
        EXPECT_EQ(std::strtod(CsvWriter::fmt(v).c_str(), nullptr), v) << CsvWriter::fmt(v);
    }
}

// ---- SnapshotSeries --------------------------------------------------------------------

TEST_F(IoTest, SnapshotTwoStepsReadBack) {
    const std::string out_dir = p("snaps");
    SnapshotSeries series(out_dir, "dam");
    const SnapshotData s0 = make_snapshot(0, 0.0, 3);
    const SnapshotData s1 = make_snapshot(250, 0.125, 4);
    series.write(s0);
    series.write(s1);

    const std::vector<std::string> files = series.files();
    ASSERT_EQ(files.size(), 2u);
    EXPECT_EQ(files[0], (fs::path(out_dir) / "dam_000000.h5").string());
    EXPECT_EQ(files[1], (fs::path(out_dir) / "dam_000250.h5").string());
    EXPECT_TRUE(temporaries(dir_).empty());

    for (std::size_t k = 0; k < 2; ++k) {
        const SnapshotData& s = k == 0 ? s0 : s1;
        const hsize_t n = s.type.size();
        hid_t f = H5Fopen(files[k].c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
        ASSERT_GE(f, 0) << files[k];
        EXPECT_EQ(read_dataset<double>(f, "position", H5T_NATIVE_DOUBLE, H5T_FLOAT, 8, {n, 3}),
                  s.position);
        EXPECT_EQ(read_dataset<float>(f, "velocity", H5T_NATIVE_FLOAT, H5T_FLOAT, 4, {n, 3}),
                  s.velocity);
        EXPECT_EQ(read_dataset<float>(f, "density", H5T_NATIVE_FLOAT, H5T_FLOAT, 4, {n}),
                  s.density);
        EXPECT_EQ(read_dataset<float>(f, "pressure", H5T_NATIVE_FLOAT, H5T_FLOAT, 4, {n}),
                  s.pressure);
        EXPECT_EQ(read_dataset<std::uint8_t>(f, "type", H5T_NATIVE_UINT8, H5T_INTEGER, 1, {n}),
                  s.type);
        EXPECT_EQ(read_dataset<std::uint32_t>(f, "id", H5T_NATIVE_UINT32, H5T_INTEGER, 4, {n}),
                  s.id);
        const auto conn =
            read_dataset<std::uint32_t>(f, "connectivity", H5T_NATIVE_UINT32, H5T_INTEGER, 4, {n});
        for (std::size_t i = 0; i < conn.size(); ++i) EXPECT_EQ(conn[i], i);
        EXPECT_EQ(read_attribute<double>(f, "time", H5T_NATIVE_DOUBLE), s.time);
        EXPECT_EQ(read_attribute<std::int64_t>(f, "step", H5T_NATIVE_INT64), s.step);
        EXPECT_GE(H5Fclose(f), 0);
    }

    const std::string xmf = slurp(series.xdmf_path());
    EXPECT_EQ(series.xdmf_path(), (fs::path(out_dir) / "dam.xmf").string());
    EXPECT_NE(xmf.find("<?xml"), std::string::npos);
    EXPECT_NE(xmf.find("CollectionType=\"Temporal\""), std::string::npos);
    EXPECT_NE(xmf.find(">dam_000000.h5:/position<"), std::string::npos);  // relative paths
    EXPECT_NE(xmf.find(">dam_000250.h5:/position<"), std::string::npos);
    EXPECT_EQ(xmf.find(out_dir), std::string::npos);
    EXPECT_NE(xmf.find("NumberOfElements=\"3\""), std::string::npos);
    EXPECT_NE(xmf.find("NumberOfElements=\"4\""), std::string::npos);
    EXPECT_NE(xmf.find("<Time Value=\"0\"/>"), std::string::npos);
    EXPECT_NE(xmf.find("<Time Value=\"0.125\"/>"), std::string::npos);
    EXPECT_NE(xmf.find("Dimensions=\"4 3\" NumberType=\"Float\" Precision=\"8\""), std::string::npos);
    EXPECT_NE(xmf.find("NumberType=\"UChar\" Precision=\"1\" Format=\"HDF\">dam_000250.h5:/type<"),
              std::string::npos);
    EXPECT_NE(xmf.find("NumberType=\"UInt\" Precision=\"4\" Format=\"HDF\">dam_000250.h5:/id<"),
              std::string::npos);
    // Balanced: one collection + one grid per snapshot, each attribute opened and closed.
    EXPECT_EQ(count(xmf, "<Grid "), 3u);
    EXPECT_EQ(count(xmf, "</Grid>"), 3u);
    EXPECT_EQ(count(xmf, "<Attribute "), 10u);
    EXPECT_EQ(count(xmf, "</Attribute>"), 10u);
    EXPECT_EQ(count(xmf, "<DataItem "), count(xmf, "</DataItem>"));
    EXPECT_NE(xmf.rfind("</Xdmf>\n"), std::string::npos);
}

TEST_F(IoTest, SnapshotRewriteSameStepReplacesEntry) {
    SnapshotSeries series(p("s"), "run");
    series.write(make_snapshot(7, 1.0, 2));
    series.write(make_snapshot(7, 2.0, 5));
    ASSERT_EQ(series.files().size(), 1u);
    const std::string xmf = slurp(series.xdmf_path());
    EXPECT_EQ(count(xmf, "<Grid "), 2u);
    EXPECT_NE(xmf.find("NumberOfElements=\"5\""), std::string::npos);
    EXPECT_EQ(xmf.find("NumberOfElements=\"2\""), std::string::npos);
}

TEST_F(IoTest, SnapshotEmptyIsWritten) {
    SnapshotSeries series(p("s"), "empty");
    series.write(make_snapshot(1, 0.5, 0));
    hid_t f = H5Fopen(series.files().at(0).c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    EXPECT_TRUE(read_dataset<double>(f, "position", H5T_NATIVE_DOUBLE, H5T_FLOAT, 8, {0, 3}).empty());
    H5Fclose(f);
}

TEST_F(IoTest, SnapshotUnderRegularFileThrowsWithPath) {
    std::ofstream(p("blocker")) << "x";
    const std::string out_dir = p("blocker/snaps");
    SnapshotSeries series(out_dir, "dam");
    try {
        series.write(make_snapshot(0, 0.0, 3));
        FAIL() << "expected RunError";
    } catch (const RunError& e) {
        EXPECT_NE(std::string(e.what()).find(out_dir), std::string::npos) << e.what();
    }
    EXPECT_TRUE(series.files().empty());
}

TEST_F(IoTest, SnapshotHdf5FailureThrowsWithPathAndCleansUp) {
    // A directory squatting on the temporary's name makes H5Fcreate itself fail.
    SnapshotSeries series(p("s"), "dam");
    const std::string h5 = p("s/dam_000042.h5");
    fs::create_directories(h5 + ".tmp-" + std::to_string(::getpid()) + "/keep");
    try {
        series.write(make_snapshot(42, 0.0, 3));
        FAIL() << "expected RunError";
    } catch (const RunError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(h5), std::string::npos) << msg;
        EXPECT_NE(msg.find("HDF5"), std::string::npos) << msg;
    }
    EXPECT_FALSE(fs::exists(h5));
    EXPECT_FALSE(fs::exists(series.xdmf_path()));
    EXPECT_TRUE(series.files().empty());
}

TEST_F(IoTest, SnapshotRejectsMismatchedSizes) {
    SnapshotSeries series(p("s"), "dam");
    SnapshotData d = make_snapshot(3, 0.0, 4);
    d.pressure.pop_back();
    EXPECT_THROW(series.write(d), RunError);
    EXPECT_FALSE(fs::exists(p("s/dam_000003.h5")));
    EXPECT_THROW(SnapshotSeries(p("s"), "a/b"), InputError);
    EXPECT_THROW(SnapshotSeries(p("s"), ""), InputError);
}
