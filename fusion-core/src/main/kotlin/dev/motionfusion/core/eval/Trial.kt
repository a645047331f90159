/*
 * A recording with optical ground truth, in the layout of the BROAD subset: a folder with
 * input.csv(.gz) (t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]; s, rad/s, m/s², µT, Android device frame)
 * and truth.csv(.gz) (t_s,qw,qx,qy,qz,movement; sensor → ENU, Hamilton, scalar first; empty or
 * NaN while occluded; movement = 1 on scored samples), one truth row per input row.
 */
package dev.motionfusion.core.eval

import dev.motionfusion.core.io.ImuTableReader
import dev.motionfusion.core.io.Inputs
import java.io.File

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
         * Loads the trial in [dir] (input.csv.gz or input.csv, truth.csv.gz or truth.csv). The input is
         * an IMU table read by [ImuTableReader]; empty or "nan" truth fields read as NaN.
         * @throws IllegalArgumentException for missing files, bad headers or misaligned rows.
         * @throws dev.motionfusion.core.io.DataFormatException for a malformed input table.
         */
        public fun load(dir: File): Trial {
            val input = ImuTableReader.open(locate(dir, "input").toPath()).use { r -> r.asSequence().toList() to r.hasMagnetometer }
            val rows = input.first
            val hasMag = input.second
            val truthFile = locate(dir, "truth")
            val truth = Inputs.reader(truthFile.toPath()).use { reader ->
                val header = reader.readLine()?.split(',')?.map { it.trim() }
                require(header == TRUTH_HEADER) { "${truthFile.path}: header $header, expected $TRUTH_HEADER" }
                reader.lineSequence().filter { it.isNotBlank() }.map { line ->
                    val parts = line.split(',')
                    require(parts.size == TRUTH_HEADER.size) { "${truthFile.path}: ${parts.size} fields in '$line'" }
                    DoubleArray(parts.size) { k -> parts[k].trim().let { v -> if (v.isEmpty() || v.equals("nan", ignoreCase = true)) Double.NaN else v.toDouble() } }
                }.toList()
            }
            require(rows.size == truth.size) { "${dir.name}: ${rows.size} input rows but ${truth.size} truth rows" }
            val n = rows.size
            for (i in 0 until n) require(truth[i][0] == rows[i].timeS) { "${dir.name}: row $i truth time ${truth[i][0]} ≠ input time ${rows[i].timeS}" }
            return Trial(
                dir.name,
                DoubleArray(n) { rows[it].timeS },
                Array(n) { rows[it].let { r -> doubleArrayOf(r.gx, r.gy, r.gz, r.ax, r.ay, r.az, r.mx, r.my, r.mz) } },
                hasMag,
                Array(n) { truth[it].copyOfRange(1, 5) },
                BooleanArray(n) { truth[it][5] == 1.0 },
            )
        }

        /** True when [dir] holds a trial (an input and a truth file). */
        public fun isTrial(dir: File): Boolean =
            listOf("input", "truth").all { File(dir, "$it.csv.gz").isFile || File(dir, "$it.csv").isFile }

        private fun locate(dir: File, stem: String): File =
            listOf(File(dir, "$stem.csv.gz"), File(dir, "$stem.csv")).firstOrNull { it.isFile }
                ?: throw IllegalArgumentException("${dir.path}: no $stem.csv.gz or $stem.csv")

        private val TRUTH_HEADER = listOf("t_s", "qw", "qx", "qy", "qz", "movement")
    }
}
