// PCL's side of tests/python/check_vfh_pcl.py: for each cluster of IN, the VFHSignature308
// PCL computes (a) from the given normals and (b) from PCL's own NormalEstimation (k nearest
// neighbours, turned towards the viewpoint), and PCL's normals.
//
// IN:  u32 clusters, u32 k; per cluster: u32 n, f32 viewpoint[3], n x f32[6] (x y z nx ny nz)
// OUT: per cluster: f32[308] (given normals), f32[308] (PCL normals), n x f32[3] PCL normals
//
// Build: g++ -O2 -std=c++17 -I<pcl-1.13 include> -I<flann include> -I/usr/include/eigen3 \
//        pcl_vfh.cpp -o pcl_vfh -lpcl_features -lpcl_search -lpcl_kdtree -lpcl_common
#include <cstdint>
#include <cstdio>
#include <vector>

#include <pcl/features/normal_3d.h>
#include <pcl/features/vfh.h>
#include <pcl/point_types.h>
#include <pcl/search/brute_force.h>

template <typename T> static bool read(FILE *f, T *v, size_t n = 1) {
  return fread(v, sizeof(T), n, f) == n;
}

static pcl::VFHSignature308 vfh(const pcl::PointCloud<pcl::PointXYZ>::Ptr &cloud,
                                const pcl::PointCloud<pcl::Normal>::Ptr &normals,
                                const float vp[3]) {
  pcl::VFHEstimation<pcl::PointXYZ, pcl::Normal, pcl::VFHSignature308> estimation;
  estimation.setInputCloud(cloud);
  estimation.setInputNormals(normals);
  estimation.setSearchMethod(pcl::search::BruteForce<pcl::PointXYZ>::Ptr(
      new pcl::search::BruteForce<pcl::PointXYZ>));
  estimation.setViewPoint(vp[0], vp[1], vp[2]);
  pcl::PointCloud<pcl::VFHSignature308> out;
  estimation.compute(out);
  return out[0];
}

int main(int argc, char **argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s IN OUT\n", argv[0]);
    return 2;
  }
  FILE *in = fopen(argv[1], "rb");
  FILE *out = fopen(argv[2], "wb");
  if (!in || !out) {
    fprintf(stderr, "cannot open files\n");
    return 2;
  }
  uint32_t clusters = 0, k = 0;
  if (!read(in, &clusters) || !read(in, &k)) return 1;
  for (uint32_t c = 0; c < clusters; ++c) {
    uint32_t n = 0;
    float vp[3];
    if (!read(in, &n) || !read(in, vp, 3)) return 1;
    std::vector<float> data(6 * size_t(n));
    if (!read(in, data.data(), data.size())) return 1;
    pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
    pcl::PointCloud<pcl::Normal>::Ptr given(new pcl::PointCloud<pcl::Normal>);
    for (uint32_t i = 0; i < n; ++i) {
      const float *d = &data[6 * size_t(i)];
      cloud->push_back(pcl::PointXYZ(d[0], d[1], d[2]));
      given->push_back(pcl::Normal(d[3], d[4], d[5]));
    }
    pcl::VFHSignature308 a = vfh(cloud, given, vp);

    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
    ne.setInputCloud(cloud);
    ne.setSearchMethod(pcl::search::BruteForce<pcl::PointXYZ>::Ptr(
        new pcl::search::BruteForce<pcl::PointXYZ>));
    ne.setKSearch(int(k));
    ne.setViewPoint(vp[0], vp[1], vp[2]);
    pcl::PointCloud<pcl::Normal>::Ptr own(new pcl::PointCloud<pcl::Normal>);
    ne.compute(*own);
    pcl::VFHSignature308 b = vfh(cloud, own, vp);

    fwrite(a.histogram, sizeof(float), 308, out);
    fwrite(b.histogram, sizeof(float), 308, out);
    for (const auto &q : *own) fwrite(q.normal, sizeof(float), 3, out);
  }
  fclose(out);
  return 0;
}
