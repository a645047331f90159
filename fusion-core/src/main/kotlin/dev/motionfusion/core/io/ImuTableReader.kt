/*
 * The plain IMU table: one CSV row per instant with every sensor sampled together.
 *
 *     t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]
 *
 * t_s in seconds, gyroscope in rad/s, accelerometer in m/s² (specific force: +9.81 on the
 * up axis at rest, as Android's TYPE_ACCELEROMETER), magnetometer in µT, all in the device
 * frame. Columns are found by name, so their order is free and extra columns are ignored.
 * A magnetometer field may be empty (no reading at that instant); other fields may not.
 * Numbers use '.' as decimal separator; NaN and Infinity are read as such (the filter
 * skips them). The file may be gzip-compressed. Reading streams: memory does not grow
 * with the file.
 */
package dev.motionfusion.core.io

import java.io.BufferedReader
import java.io.Closeable
import java.io.InputStream
import java.nio.file.Path

/** One row of an IMU table. Units: s, rad/s, m/s², µT; magnetometer NaN when absent. */
public data class ImuSample(
    val timeS: Double,
    val gx: Double, val gy: Double, val gz: Double,
    val ax: Double, val ay: Double, val az: Double,
    val mx: Double, val my: Double, val mz: Double,
)

/**
 * Streams the rows of an IMU table. Malformed content throws [DataFormatException] naming
 * the source, line and column.
 */
public class ImuTableReader private constructor(
    private val reader: BufferedReader,
    private val sourceName: String,
) : Closeable, Iterator<ImuSample> {

    /** True when the table has magnetometer columns. */
    public val hasMagnetometer: Boolean

    private val index = IntArray(COLUMNS.size) { -1 }
    private var lineNumber = 0L
    private var next: ImuSample? = null
    private val fields = CsvLine()

    init {
        val header = readNonBlankLine() ?: throw DataFormatException(sourceName, 1, 0, "empty file: expected a header ${COLUMNS.joinToString(",")}")
        fields.split(header.removePrefix(BOM))
        for (i in 0 until fields.count) {
            val c = COLUMNS.indexOf(fields.text(i).trim().removeSurrounding("\"").lowercase())
            if (c >= 0 && index[c] < 0) index[c] = i
        }
        val missingRequired = COLUMNS.take(REQUIRED).filterIndexed { c, _ -> index[c] < 0 }
        if (missingRequired.isNotEmpty()) {
            throw DataFormatException(sourceName, lineNumber, 1,
                "header lacks column(s) ${missingRequired.joinToString(",")}; expected ${COLUMNS.joinToString(",")} (magnetometer optional)")
        }
        val magPresent = (REQUIRED until COLUMNS.size).count { index[it] >= 0 }
        if (magPresent in 1 until COLUMNS.size - REQUIRED) {
            throw DataFormatException(sourceName, lineNumber, 1, "header has only some of mx,my,mz: give all three or none")
        }
        hasMagnetometer = magPresent > 0
    }

    override fun hasNext(): Boolean {
        if (next == null) next = readRow()
        return next != null
    }

    override fun next(): ImuSample {
        if (!hasNext()) throw NoSuchElementException("end of $sourceName")
        return next!!.also { next = null }
    }

    override fun close(): Unit = reader.close()

    private fun readNonBlankLine(): String? {
        while (true) {
            val l = reader.readLine() ?: return null
            lineNumber++
            if (l.isNotBlank()) return l
        }
    }

    private fun readRow(): ImuSample? {
        val line = readNonBlankLine() ?: return null
        fields.split(line)
        val v = DoubleArray(COLUMNS.size) { Double.NaN }
        for (c in COLUMNS.indices) {
            val i = index[c]
            if (i < 0) continue
            if (i >= fields.count) {
                throw DataFormatException(sourceName, lineNumber, line.length + 1,
                    "row has ${fields.count} fields, column ${COLUMNS[c]} is field ${i + 1}")
            }
            val optional = c >= REQUIRED
            v[c] = try {
                fields.parseDouble(i, optional)
            } catch (e: FieldError) {
                throw DataFormatException(sourceName, lineNumber, fields.start(i) + 1, "column ${COLUMNS[c]}: ${e.reason}")
            }
        }
        return ImuSample(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9])
    }

    public companion object {
        /** Column names in canonical order; the first [REQUIRED] are mandatory. */
        public val COLUMNS: List<String> = listOf("t_s", "gx", "gy", "gz", "ax", "ay", "az", "mx", "my", "mz")
        private const val REQUIRED = 7
        private const val BOM = "\uFEFF"

        /** Opens [path] (plain or gzip). The caller closes the reader. */
        public fun open(path: Path): ImuTableReader =
            open(java.nio.file.Files.newInputStream(path), path.fileName?.toString() ?: path.toString())

        /** Reads from [input] (plain or gzip); [sourceName] names it in errors. */
        public fun open(input: InputStream, sourceName: String): ImuTableReader {
            val r = Inputs.reader(input)
            try {
                return ImuTableReader(r, sourceName)
            } catch (e: Throwable) {
                r.close()
                throw e
            }
        }
    }
}
