/*
 * Sensor Logger exports (docs/IMPORT.md): a zip or folder with one CSV per sensor, header
 * `time,seconds_elapsed,z,y,x` (UTC ns as an integer, s, then the axes; columns are found by
 * name), and, in newer exports, Metadata.csv naming the platform and (from app 1.29) whether
 * "Standardise Units & Frames" was on.
 *
 * Sign and units: Android exports are in the Android convention (m/s², specific force +9.81 on
 * the up axis at rest). iOS exports that were not standardised carry CoreMotion's convention:
 * acceleration and gravity with the opposite sign, AccelerometerUncalibrated.csv in g. Gyroscope
 * and magnetometer axes and signs agree on both platforms.
 */
package dev.motionfusion.core.input

import dev.motionfusion.core.WorldFrame

import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FileSet
import dev.motionfusion.core.event.SessionStream

/** The phone platform of an export, where it decides sign conventions and units. */
public enum class Platform { ANDROID, IOS }

/** How an export's streams are opened: one source per stream, and what the user should know. */
internal class ImportPlan(val sources: List<StreamSource>, val notes: List<String>) {
    val streams: Set<SessionStream> get() = sources.mapTo(LinkedHashSet()) { it.stream }
}

internal class StreamSource(val stream: SessionStream, val open: (FileSet) -> dev.motionfusion.core.event.StreamCursor)

internal object SensorLoggerImport {
    /** True when [header] is a Sensor Logger CSV header. */
    fun recognises(header: String): Boolean =
        ByteCsvReader.headerNames(header).take(2) == listOf("time", "seconds_elapsed")

    /** What Metadata.csv says: platform, and whether units and frames were standardised (null when not stated). */
    private class Metadata(val platform: Platform?, val standardised: Boolean?, val appVersion: String?)

    private fun metadata(files: FileSet, dir: String): Metadata? {
        val path = files.find(dir, "Metadata.csv") ?: return null
        files.csv(path).use { csv ->
            if (!csv.nextLine()) return null
            val names = csv.names()
            if (!csv.nextLine()) return null
            fun value(n: String): String? = names.indexOf(n).takeIf { it in 0 until csv.count }?.let { csv.text(it).trim() }
            val platform = when (value("platform")?.lowercase()) {
                "ios" -> Platform.IOS
                "android" -> Platform.ANDROID
                null, "" -> null
                else -> throw DataFormatException(files.displayName(path), 2, csv.column(names.indexOf("platform")),
                    "platform '${csv.excerpt(names.indexOf("platform"))}' is neither android nor ios")
            }
            val standardised = value("standardisation")?.lowercase()?.let { it == "true" }
            return Metadata(platform, standardised, value("appVersion"))
        }
    }

    /**
     * The platform where Metadata.csv does not say: column orders that differ between the two
     * apps, else the unit of AccelerometerUncalibrated.csv (g on iOS: a norm near 1 at the start).
     */
    private fun inferPlatform(files: FileSet, dir: String): Platform? {
        files.find(dir, "Orientation.csv")?.let { files.firstLine(it) }?.let { h ->
            val names = ByteCsvReader.headerNames(h)
            if (names.getOrNull(2) == "qz") return Platform.ANDROID
            if (names.getOrNull(2) == "yaw") return Platform.IOS
        }
        files.find(dir, "Location.csv")?.let { files.firstLine(it) }?.let { h ->
            if ("altitudeAboveMeanSeaLevel" in ByteCsvReader.headerNames(h)) return Platform.IOS
        }
        val uncalibrated = files.find(dir, "AccelerometerUncalibrated.csv") ?: return null
        files.csv(uncalibrated).use { csv ->
            if (!csv.nextLine()) return null
            val idx = listOf("x", "y", "z").map { csv.names().indexOf(it) }
            if (idx.any { it < 0 }) return null
            val norms = ArrayList<Double>()
            while (norms.size < 50 && csv.nextLine()) {
                val n = runCatching { kotlin.math.sqrt(idx.sumOf { val v = csv.parseDouble(it); v * v }) }.getOrNull() ?: return null
                norms += n
            }
            if (norms.isEmpty()) return null
            val median = norms.sorted()[norms.size / 2]
            return when {
                median in 0.5..2.0 -> Platform.IOS
                median in 5.0..20.0 -> Platform.ANDROID
                else -> null
            }
        }
    }

    fun plan(files: FileSet, dir: String, platformOverride: Platform?): ImportPlan {
        val notes = ArrayList<String>()
        val meta = metadata(files, dir)
        val platform: Platform
        val standardised: Boolean
        when {
            platformOverride != null -> {
                platform = platformOverride
                standardised = meta?.standardised ?: false
                if (meta?.platform != null && meta.platform != platformOverride) notes += "Metadata.csv says ${meta.platform.name.lowercase()}; --platform ${platformOverride.name.lowercase()} overrides it"
            }
            meta?.platform != null -> {
                platform = meta.platform
                standardised = meta.standardised ?: false
            }
            else -> {
                val inferred = inferPlatform(files, dir)
                platform = inferred ?: Platform.ANDROID
                standardised = false
                notes += if (inferred != null) {
                    "${if (meta == null) "no Metadata.csv" else "no platform in Metadata.csv"}; ${inferred.name.lowercase()} inferred from the export's columns and units (override with --platform)"
                } else {
                    "no Metadata.csv: assumed an Android export (if it comes from an iPhone, give --platform ios)"
                }
            }
        }
        // CoreMotion's sign: acceleration and gravity point the other way; uncalibrated acceleration in g.
        val iosRaw = platform == Platform.IOS && !standardised
        val accSign = if (iosRaw) -1.0 else 1.0
        val uncalibratedAccScale = if (iosRaw) -STANDARD_GRAVITY else 1.0

        fun map(name: String, stream: SessionStream, scale: Double, columns: List<String>): ColumnMap? {
            val path = files.find(dir, name) ?: return null
            val header = files.firstLine(path) ?: return null
            val names = ByteCsvReader.headerNames(header)
            fun col(n: String): Int = names.indexOf(n).also {
                if (it < 0) throw DataFormatException(files.displayName(path), 1, 0, "header lacks column '$n' (got ${ByteCsvReader.escapedExcerpt(header)})")
            }
            val idx = IntArray(stream.valueCount) { k -> columns.getOrNull(k)?.let { col(it) } ?: -1 }
            return ColumnMap(stream, path, Dialect.COMMA, col("time"), true, idx, DoubleArray(idx.size) { scale })
        }
        val xyz = listOf("x", "y", "z")
        val sources = ArrayList<StreamSource>()

        val total = map("TotalAcceleration.csv", SessionStream.ACCELEROMETER, accSign, xyz)
        val linear = map("Accelerometer.csv", SessionStream.ACCELEROMETER, accSign, xyz)
        val gravity = map("Gravity.csv", SessionStream.ACCELEROMETER, accSign, xyz)
        val uncalibrated = map("AccelerometerUncalibrated.csv", SessionStream.ACCELEROMETER, uncalibratedAccScale, xyz)
        when {
            total != null -> sources += StreamSource(SessionStream.ACCELEROMETER) { total.open(it) }
            linear != null && gravity != null -> sources += StreamSource(SessionStream.ACCELEROMETER) { f ->
                val a = linear.open(f)
                try { SumCursor(a, gravity.open(f)) } catch (e: Throwable) { a.close(); throw e }
            }
            uncalibrated != null -> {
                sources += StreamSource(SessionStream.ACCELEROMETER) { uncalibrated.open(it) }
                if (linear != null) notes += "Accelerometer.csv has no gravity and there is no Gravity.csv: AccelerometerUncalibrated.csv used instead"
            }
            linear != null -> throw DataFormatException(files.displayName(linear.path), 0, 0,
                "Sensor Logger's Accelerometer.csv is acceleration WITHOUT gravity and there is neither Gravity.csv to add back nor " +
                    "AccelerometerUncalibrated.csv; the filter needs the accelerometer with gravity (enable 'Total Acceleration' or 'Gravity' when recording)")
            else -> throw DataFormatException(files.name, 0, 0,
                "Sensor Logger export without accelerometer data (TotalAcceleration.csv, Accelerometer.csv with Gravity.csv, or AccelerometerUncalibrated.csv): nothing to replay")
        }
        val gyro = map("Gyroscope.csv", SessionStream.GYROSCOPE, 1.0, xyz)
            ?: map("GyroscopeUncalibrated.csv", SessionStream.GYROSCOPE, 1.0, xyz)?.also { notes += "${if (files.find(dir, "Gyroscope.csv") != null) "Gyroscope.csv holds no reading" else "no Gyroscope.csv"}: GyroscopeUncalibrated.csv used (drift is left to the filter's bias estimation)" }
            ?: throw DataFormatException(files.name, 0, 0, "Sensor Logger export without Gyroscope.csv or GyroscopeUncalibrated.csv: nothing to replay")
        sources += StreamSource(SessionStream.GYROSCOPE) { gyro.open(it) }
        val mag = map("Magnetometer.csv", SessionStream.MAGNETOMETER, 1.0, xyz)
        if (mag != null) {
            sources += StreamSource(SessionStream.MAGNETOMETER) { mag.open(it) }
        } else if (files.find(dir, "MagnetometerUncalibrated.csv") != null) {
            notes += "only MagnetometerUncalibrated.csv (hard-iron bias not removed): replayed without magnetometer (6D)"
        }
        // The uncalibrated streams as their own (calibration and the phone's bias read them); Sensor
        // Logger writes no bias columns, so values[3..5] stay unknown.
        for ((file, stream) in listOf("GyroscopeUncalibrated.csv" to SessionStream.GYROSCOPE_UNCALIBRATED, "MagnetometerUncalibrated.csv" to SessionStream.MAGNETOMETER_UNCALIBRATED)) {
            map(file, stream, 1.0, xyz)?.let { u -> sources += StreamSource(stream) { u.open(it) } }
        }
        // The phone's own orientation: Android's rotation vector is sensor → ENU already; CoreMotion's
        // attitude is sensor → its x-north-z-vertical reference (NWU, true north), turned here into ENU.
        map("Orientation.csv", SessionStream.ROTATION_VECTOR, 1.0, listOf("qx", "qy", "qz", "qw"))?.let { o ->
            sources += StreamSource(SessionStream.ROTATION_VECTOR) { if (iosRaw) WorldFrameCursor(o.open(it), WorldFrame.NWU) else o.open(it) }
        }
        return ImportPlan(sources, notes)
    }
}
