/*
 * A recording with optical ground truth, in the layout of the BROAD subset: a folder with
 * input.csv(.gz) (t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]; s, rad/s, m/s², µT, Android device frame)
 * and truth.csv(.gz) (t_s,qw,qx,qy,qz,movement; sensor → ENU, Hamilton, scalar first; empty or
 * NaN while occluded; movement = 1 on scored samples), one truth row per input row.
 */
package dev.motionfusion.core.eval

import java.io.BufferedReader
import java.io.File
import java.io.InputStreamReader
import java.util.zip.GZIPInputStream

/**
 * One trial in memory.
 *
 * @property imu n rows of [gx, gy, gz, ax, ay, az, mx, my, mz] (mx..mz NaN when [hasMag] is false).
 * @property truth n rows of [qw, qx, qy, qz] (sensor → ENU), NaN where unknown.
 */
public class Trial(
    public val name: String,
    public val timeS: DoubleArray,
    public val imu: Array<DoubleArray>,
    public val hasMag: Boolean,
    public val truth: Array<DoubleArray>,
    public val movement: BooleanArray,
) {
    init {
        val n = timeS.size
        require(imu.size == n && truth.size == n && movement.size == n) { "$name: inconsistent lengths" }
    }

    public val size: Int get() = timeS.size

    public companion object {
        /**
         * Loads the trial in [dir] (input.csv.gz or input.csv, truth.csv.gz or truth.csv).
         * @throws IllegalArgumentException for missing files, bad headers or misaligned rows.
         */
        public fun load(dir: File): Trial {
            val input = readCsv(locate(dir, "input"))
            val truth = readCsv(locate(dir, "truth"))
            val inHeader = input.first
            require(inHeader.take(7) == listOf("t_s", "gx", "gy", "gz", "ax", "ay", "az")) { "${dir.name}: unexpected input header $inHeader" }
            val hasMag = inHeader.size >= 10 && inHeader.subList(7, 10) == listOf("mx", "my", "mz")
            require(truth.first == listOf("t_s", "qw", "qx", "qy", "qz", "movement")) { "${dir.name}: unexpected truth header ${truth.first}" }
            val rows = input.second
            val truthRows = truth.second
            require(rows.size == truthRows.size) { "${dir.name}: ${rows.size} input rows but ${truthRows.size} truth rows" }
            val n = rows.size
            val t = DoubleArray(n)
            val imu = Array(n) { DoubleArray(9) { Double.NaN } }
            val q = Array(n) { DoubleArray(4) }
            val movement = BooleanArray(n)
            for (i in 0 until n) {
                val r = rows[i]
                val tr = truthRows[i]
                t[i] = r[0]
                require(tr[0] == r[0]) { "${dir.name}: row $i truth time ${tr[0]} ≠ input time ${r[0]}" }
                for (k in 0 until (if (hasMag) 9 else 6)) imu[i][k] = r[k + 1]
                for (k in 0 until 4) q[i][k] = tr[k + 1]
                movement[i] = tr[5] == 1.0
            }
            return Trial(dir.name, t, imu, hasMag, q, movement)
        }

        /** True when [dir] holds a trial (an input and a truth file). */
        public fun isTrial(dir: File): Boolean =
            listOf("input", "truth").all { File(dir, "$it.csv.gz").isFile || File(dir, "$it.csv").isFile }

        private fun locate(dir: File, stem: String): File =
            listOf(File(dir, "$stem.csv.gz"), File(dir, "$stem.csv")).firstOrNull { it.isFile }
                ?: throw IllegalArgumentException("${dir.path}: no $stem.csv.gz or $stem.csv")

        /** Header and numeric rows; empty fields and "nan" read as NaN. */
        private fun readCsv(file: File): Pair<List<String>, List<DoubleArray>> {
            val stream = file.inputStream().let { if (file.name.endsWith(".gz")) GZIPInputStream(it) else it }
            BufferedReader(InputStreamReader(stream, Charsets.UTF_8)).use { reader ->
                val header = reader.readLine()?.split(',')?.map { it.trim() }
                    ?: throw IllegalArgumentException("${file.path}: empty")
                val rows = ArrayList<DoubleArray>()
                reader.lineSequence().filter { it.isNotBlank() }.forEach { line ->
                    val parts = line.split(',')
                    require(parts.size == header.size) { "${file.path}: ${parts.size} fields in '$line'" }
                    rows.add(DoubleArray(parts.size) { k -> parts[k].trim().let { s -> if (s.isEmpty() || s.equals("nan", ignoreCase = true)) Double.NaN else s.toDouble() } })
                }
                return header to rows
            }
        }
    }
}
