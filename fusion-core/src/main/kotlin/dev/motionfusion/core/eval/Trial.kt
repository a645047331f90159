/*
 * A recording with optical ground truth, in the layout of the BROAD subset: a folder with
 * input.csv(.gz) (t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]; s, rad/s, m/s², µT, Android device frame)
 * and truth.csv(.gz) (t_s,qw,qx,qy,qz,movement; sensor → ENU, Hamilton, scalar first; empty or
 * NaN while occluded; movement = 1 on scored samples), one truth row per input row. Trials are
 * streamed row by row: memory does not grow with their length.
 */
package dev.motionfusion.core.eval

import dev.motionfusion.core.input.ImuTableReader
import dev.motionfusion.core.input.QuaternionTableReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.InputLimits
import dev.motionfusion.core.io.Json
import java.io.Closeable
import java.io.File

/** One trial folder: [input] and [truth] tables, read by [open]. */
public class Trial private constructor(public val name: String, public val input: File, public val truth: File) {
    /** True when the input table has magnetometer columns. */
    public val hasMag: Boolean by lazy { ImuTableReader.open(input.toPath()).use { it.hasMagnetometer } }

    /**
     * True when the trial's meta.json says it is scored "6d…": with one constant heading offset removed
     * for every method (ADVIO's truth has no north). Every score of it then removes the offset.
     */
    public val headingOffsetScored: Boolean by lazy {
        val meta = File(input.parentFile, "meta.json")
        meta.isFile && meta.length() < 1_000_000 &&
            (Json.parse(meta.readText(), meta.path) as? Map<*, *>)?.get("scoring").let { it is String && it.trim().lowercase().startsWith("6d") }
    }

    /** The trial's rows from the start; the caller closes the reader. */
    @JvmOverloads
    public fun open(limits: InputLimits = InputLimits()): TrialReader {
        val imu = ImuTableReader.open(input.toPath(), limits)
        try {
            return TrialReader(name, imu, QuaternionTableReader.open(truth.toPath(), limits), truth.path)
        } catch (e: Throwable) {
            imu.close()
            throw e
        }
    }

    public companion object {
        /**
         * The trial in [dir] (input.csv.gz or input.csv, truth.csv.gz or truth.csv).
         * @throws DataFormatException when a file is missing.
         */
        @JvmStatic
        public fun load(dir: File): Trial = Trial(dir.name, locate(dir, "input"), locate(dir, "truth"))

        /** True when [dir] holds a trial (an input and a truth file). */
        @JvmStatic
        public fun isTrial(dir: File): Boolean =
            listOf("input", "truth").all { File(dir, "$it.csv.gz").isFile || File(dir, "$it.csv").isFile }

        private fun locate(dir: File, stem: String): File =
            listOf(File(dir, "$stem.csv.gz"), File(dir, "$stem.csv")).firstOrNull { it.isFile }
                ?: throw DataFormatException(dir.path, 0, 0, "no $stem.csv.gz or $stem.csv: not a trial folder")
    }
}

/**
 * A trial's rows in lock step: [timeS], [imu] (gx…mz, mx…mz NaN without magnetometer), [truth]
 * [w, x, y, z] (NaN where unknown) and [scored]; arrays reused by the next call.
 */
public class TrialReader internal constructor(
    private val name: String,
    private val imuReader: ImuTableReader,
    private val truthReader: QuaternionTableReader,
    private val truthName: String,
) : Closeable {
    public val hasMag: Boolean get() = imuReader.hasMagnetometer
    public val timeS: Double get() = imuReader.timeS
    public val imu: DoubleArray get() = imuReader.row
    public val truth: DoubleArray get() = truthReader.q
    public val scored: Boolean get() = truthReader.scored
    private var row = 0L

    public fun next(): Boolean {
        val a = imuReader.next()
        val b = truthReader.next()
        if (a != b) throw DataFormatException(truthName, 0, 0, "$name: ${if (a) "fewer" else "more"} truth rows than input rows (they must pair up; input row ${row + 1})")
        if (!a) return false
        row++
        if (truthReader.timeS != imuReader.timeS) {
            throw DataFormatException(truthName, row + 1, 1, "truth time ${truthReader.timeS} ≠ input time ${imuReader.timeS} (row $row; the tables must pair up row by row)")
        }
        return true
    }

    override fun close() {
        try { imuReader.close() } finally { truthReader.close() }
    }
}
