/*
 * Importers of other apps' exports and of the plain IMU table, as SessionEvents. What is mapped
 * and how units and frames convert is documented in docs/IMPORT.md; keep the two in step.
 */
package dev.motionfusion.core.recording

import dev.motionfusion.core.io.CsvLine
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.ImuTableReader
import dev.motionfusion.core.io.Inputs
import dev.motionfusion.core.session.SessionEvents
import dev.motionfusion.core.session.SessionStream
import dev.motionfusion.core.session.StreamCursor
import kotlin.math.roundToLong

/** The plain IMU table as events: per row accelerometer, magnetometer (if any), then gyroscope, all at t_s. */
internal class ImuTableEvents(private val table: ImuTableReader, private val sourceName: String) : SessionEvents {
    private var row: dev.motionfusion.core.io.ImuSample? = null
    private var phase = 0
    override var stream: SessionStream = SessionStream.ACCELEROMETER
        private set
    override var timestampNs: Long = 0L
        private set
    override val values: DoubleArray = DoubleArray(3)
    override val accuracy: Int get() = SessionEvents.NO_ACCURACY

    override fun next(): Boolean {
        while (true) {
            val r = row
            if (r == null || phase == 3) {
                if (!table.hasNext()) return false
                val n = table.next()
                row = n
                phase = 0
                val t = n.timeS * 1e9
                if (!(kotlin.math.abs(t) < 9.2e18)) throw DataFormatException(sourceName, 0, 0, "time ${n.timeS} s is not a finite time (or beyond ±292 years)")
                timestampNs = t.roundToLong()
                continue
            }
            when (phase++) {
                0 -> { stream = SessionStream.ACCELEROMETER; values[0] = r.ax; values[1] = r.ay; values[2] = r.az; return true }
                1 -> {
                    if (!table.hasMagnetometer) continue
                    stream = SessionStream.MAGNETOMETER; values[0] = r.mx; values[1] = r.my; values[2] = r.mz; return true
                }
                else -> { stream = SessionStream.GYROSCOPE; values[0] = r.gx; values[1] = r.gy; values[2] = r.gz; return true }
            }
        }
    }

    override fun close(): Unit = table.close()
}

/** One column of an export mapped to a value of a stream: a header pattern and its accepted units with factors to SI. */
private class ColumnSpec(val pattern: Regex, val units: Map<String, Double>)

/** How one sensor of an export maps to a session stream. */
private class StreamSpec(val stream: SessionStream, val columns: List<ColumnSpec?>)

/**
 * phyphox exports (docs/IMPORT.md): one CSV per data set (`Accelerometer.csv`, `Gyroscope.csv`,
 * `Magnetometer.csv`, …) in a zip or folder, or a single CSV; headers like
 * `"Time (s)","Gyroscope x (rad/s)"`; comma, tab or semicolon separated; decimal point or comma.
 */
internal object PhyphoxImport {
    private val TIME = Regex("""^time \((s)\)$""")
    private fun axis(quantity: String, axis: Char) = Regex("""^$quantity $axis \(([^)]*)\)$""")

    private val ACC = StreamSpec(SessionStream.ACCELEROMETER, "xyz".map { ColumnSpec(axis("acceleration", it), mapOf("m/s^2" to 1.0, "m/s²" to 1.0)) })
    private val GYRO = StreamSpec(SessionStream.GYROSCOPE, "xyz".map { ColumnSpec(axis("gyroscope", it), mapOf("rad/s" to 1.0)) })
    private val MAG = StreamSpec(SessionStream.MAGNETOMETER, "xyz".map { ColumnSpec(axis("magnetic field", it), mapOf("µt" to 1.0, "μt" to 1.0, "ut" to 1.0)) })
    private val SPECS = listOf(ACC, GYRO, MAG)

    /** True when [header] is a phyphox header of a sensor this importer maps. */
    fun recognises(header: String): Boolean {
        val names = headerNames(header)
        return names.any { TIME.matches(it) } && SPECS.any { spec -> spec.columns.all { c -> names.any { c!!.pattern.matches(it) } } }
    }

    private fun headerNames(header: String): List<String> {
        val d = Dialect.detect(header)
        val f = CsvLine(d.separator)
        f.split(header.removePrefix("\uFEFF"))
        return (0 until f.count).map { f.text(it).trim().removeSurrounding("\"").trim().lowercase() }
    }

    /** Cursors for every file of [files] with a phyphox sensor header (other data sets are skipped). */
    fun cursors(files: InputFiles): List<StreamCursor> {
        val out = ArrayList<StreamCursor>()
        val seen = HashSet<SessionStream>()
        for (path in files.paths.sortedBy { it.count { c -> c == '/' } }) {
            if (!path.endsWith(".csv", ignoreCase = true) || path.substringAfterLast('/').startsWith("._")) continue
            val header = files.firstLine(path) ?: continue
            if (!recognises(header)) continue
            for (c in cursorsFor(files, path, header)) {
                if (seen.add(c.stream)) out += c else c.close()
            }
        }
        if (out.none { it.stream == SessionStream.GYROSCOPE }) {
            out.forEach { it.close() }
            throw DataFormatException(files.name, 0, 0, "phyphox export without gyroscope data (Gyroscope x (rad/s) …): nothing to replay")
        }
        return out
    }

    /** One cursor per sensor whose three columns are in [path] (a combined export can hold several). */
    private fun cursorsFor(files: InputFiles, path: String, header: String): List<StreamCursor> {
        val names = headerNames(header)
        val dialect = Dialect.detect(header)
        val time = names.indexOfFirst { TIME.matches(it) }
        val result = ArrayList<StreamCursor>()
        for (spec in SPECS) {
            val idx = IntArray(3)
            val scale = DoubleArray(3)
            var ok = true
            for (k in 0 until 3) {
                val c = spec.columns[k]!!
                val i = names.indexOfFirst { c.pattern.matches(it) }
                if (i < 0) { ok = false; break }
                val unit = c.pattern.find(names[i])!!.groupValues[1]
                scale[k] = c.units[unit] ?: throw DataFormatException(files.displayName(path), 1, 0,
                    "column '${names[i]}': unit '$unit' not understood (expected ${c.units.keys.joinToString(" or ")})")
                idx[k] = i
            }
            if (!ok) continue
            val reader = Inputs.reader(files.open(path))
            reader.readLine()
            result += MappedCsvCursor(spec.stream, reader, files.displayName(path), dialect, time, 1e9, idx, scale, firstLineNumber = 1)
        }
        return result
    }
}

/**
 * The sum of two streams sampled at the same instants (Sensor Logger's linear acceleration and
 * gravity, which iOS delivers together): rows whose timestamps differ are skipped on the
 * earlier side until both agree.
 */
internal class SumCursor(private val a: StreamCursor, private val b: StreamCursor) : StreamCursor {
    override val stream: SessionStream get() = a.stream
    override val timestampNs: Long get() = a.timestampNs
    override val values: DoubleArray = DoubleArray(a.values.size)
    override val accuracy: Int get() = a.accuracy

    override fun next(): Boolean {
        if (!a.next() || !b.next()) return false
        while (a.timestampNs != b.timestampNs) {
            if (a.timestampNs < b.timestampNs) { if (!a.next()) return false } else if (!b.next()) return false
        }
        for (k in values.indices) values[k] = a.values[k] + b.values[k]
        return true
    }

    override fun close() {
        try { a.close() } finally { b.close() }
    }
}

/**
 * Sensor Logger exports (docs/IMPORT.md): a zip or folder with one CSV per sensor, header
 * `time,seconds_elapsed,z,y,x` (UTC ns, s, then the axes in the order z, y, x).
 */
internal object SensorLoggerImport {
    private class FileSpec(val fileName: String, val stream: SessionStream, val columns: List<String?>)

    private val FILES = listOf(
        FileSpec("TotalAcceleration.csv", SessionStream.ACCELEROMETER, listOf("x", "y", "z")),
        FileSpec("Gyroscope.csv", SessionStream.GYROSCOPE, listOf("x", "y", "z")),
        FileSpec("Magnetometer.csv", SessionStream.MAGNETOMETER, listOf("x", "y", "z")),
        FileSpec("GyroscopeUncalibrated.csv", SessionStream.GYROSCOPE_UNCALIBRATED, listOf("x", "y", "z", null, null, null)),
        FileSpec("MagnetometerUncalibrated.csv", SessionStream.MAGNETOMETER_UNCALIBRATED, listOf("x", "y", "z", null, null, null)),
        FileSpec("Orientation.csv", SessionStream.ROTATION_VECTOR, listOf("qx", "qy", "qz", "qw", null)),
    )

    /** A cursor of the x, y, z columns of the Sensor Logger file [path] as [stream]. */
    private fun axisCursor(files: InputFiles, path: String, stream: SessionStream): StreamCursor {
        val reader = Inputs.reader(files.open(path))
        try {
            val header = reader.readLine()?.removePrefix("\uFEFF") ?: throw DataFormatException(files.displayName(path), 1, 0, "empty file")
            val names = CsvLine(',').also { it.split(header) }.let { f -> (0 until f.count).map { f.text(it).trim().removeSurrounding("\"") } }
            val idx = listOf("time", "x", "y", "z").map { n ->
                names.indexOf(n).also { if (it < 0) throw DataFormatException(files.displayName(path), 1, 0, "header lacks column '$n' (got ${names.joinToString(",")})") }
            }
            return MappedCsvCursor(stream, reader, files.displayName(path), Dialect(',', false), idx[0], 1.0, intArrayOf(idx[1], idx[2], idx[3]),
                DoubleArray(3) { 1.0 }, firstLineNumber = 1)
        } catch (e: Throwable) {
            reader.close()
            throw e
        }
    }

    /** True when [files] looks like a Sensor Logger export. */
    fun recognises(files: InputFiles): Boolean {
        val g = files.find("Gyroscope.csv") ?: files.find("TotalAcceleration.csv") ?: files.find("Accelerometer.csv") ?: return false
        val h = files.firstLine(g) ?: return false
        return h.split(',').map { it.trim().removeSurrounding("\"") }.take(2) == listOf("time", "seconds_elapsed")
    }

    fun cursors(files: InputFiles): List<StreamCursor> {
        val total = files.find("TotalAcceleration.csv")
        val linear = files.find("Accelerometer.csv")
        val gravity = files.find("Gravity.csv")
        if (total == null && linear != null && gravity == null) {
            throw DataFormatException(files.displayName(linear), 0, 0,
                "Sensor Logger's Accelerometer.csv is acceleration WITHOUT gravity and there is no Gravity.csv to add back; " +
                    "the filter needs TotalAcceleration.csv (enable 'Total Acceleration' when recording)")
        }
        val out = ArrayList<StreamCursor>()
        try {
            if (total == null && linear != null && gravity != null) {
                out += SumCursor(axisCursor(files, linear, SessionStream.ACCELEROMETER), axisCursor(files, gravity, SessionStream.ACCELEROMETER))
            }
            for (spec in FILES) {
                val path = files.find(spec.fileName) ?: continue
                val reader = Inputs.reader(files.open(path))
                val header = reader.readLine()?.removePrefix("\uFEFF")
                if (header == null) { reader.close(); continue }
                val names = CsvLine(',').also { it.split(header) }.let { f -> (0 until f.count).map { f.text(it).trim().removeSurrounding("\"") } }
                fun col(n: String): Int {
                    val i = names.indexOf(n)
                    if (i < 0) {
                        reader.close()
                        throw DataFormatException(files.displayName(path), 1, 0, "header lacks column '$n' (got ${names.joinToString(",")})")
                    }
                    return i
                }
                val time = col("time")
                val idx = IntArray(spec.columns.size) { k -> spec.columns[k]?.let { col(it) } ?: -1 }
                out += MappedCsvCursor(spec.stream, reader, files.displayName(path), Dialect(',', false), time, 1.0, idx,
                    DoubleArray(idx.size) { 1.0 }, firstLineNumber = 1)
            }
        } catch (e: Throwable) {
            out.forEach { it.close() }
            throw e
        }
        if (out.none { it.stream == SessionStream.GYROSCOPE }) {
            out.forEach { it.close() }
            throw DataFormatException(files.name, 0, 0, "Sensor Logger export without Gyroscope.csv: nothing to replay")
        }
        return out
    }
}
