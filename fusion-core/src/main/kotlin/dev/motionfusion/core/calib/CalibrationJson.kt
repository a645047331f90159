/*
 * Calibration ↔ JSON (docs/CALIBRATION.md, "The calibration file"). Vectors are arrays of three
 * numbers, matrices arrays of three rows; units in the member names (µT, rad/s, m/s²), device frame.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.Json
import dev.motionfusion.core.io.JsonObject
import dev.motionfusion.core.event.SessionStream

public object CalibrationJson {
    public const val FORMAT: String = "motion-fusion-calibration"
    public const val FORMAT_VERSION: Int = 1

    @JvmStatic
    public fun write(c: Calibration): String = Json.write(tree(c))

    /**
     * The file's JSON as a tree of maps, lists, strings, numbers and null (what [write]
     * writes), for embedding the calibration as a member of another JSON document (a session's
     * meta.json).
     */
    @JvmStatic
    public fun tree(c: Calibration): Map<String, Any?> = linkedMapOf(
        "format" to FORMAT,
        "format_version" to FORMAT_VERSION,
        "source" to c.source,
        "recording" to c.recording,
    ).also { if (c.device.isNotEmpty()) it["device"] = c.device } + linkedMapOf(
        "magnetometer" to c.magnetometer?.let { m ->
            linkedMapOf(
                "stream" to m.stream.key,
                "model" to m.model.name,
                "offset_uT" to vector(m.correction.offset),
                "matrix" to matrix(m.correction.matrix),
                "field_strength_uT" to m.fieldStrength,
                "residual_rms_uT" to m.residualRms,
                "coverage" to m.coverage,
                "samples" to m.samples,
                "magnitude_std_before_uT" to m.magnitudeStdBefore,
                "magnitude_std_after_uT" to m.magnitudeStdAfter,
            )
        },
        "gyroscope" to c.gyroscope?.let { g ->
            linkedMapOf(
                "stream" to g.stream.key,
                "bias_rad_s" to vector(g.bias),
                "bias_std_error_rad_s" to vector(g.biasStdError),
                "noise_std_rad_s" to vector(g.noiseStd),
                "still_time_s" to g.stillTimeS,
                "still_windows" to g.stillWindows,
            )
        },
        "accelerometer" to c.accelerometer?.let { a ->
            linkedMapOf(
                "stream" to a.stream.key,
                "model" to a.model.name,
                "offset_m_s2" to vector(a.correction.offset),
                "matrix" to matrix(a.correction.matrix),
                "gravity_m_s2" to a.gravity,
                "poses" to a.poses,
                "residual_rms_m_s2" to a.residualRms,
            )
        },
        "refused" to LinkedHashMap(c.refused),
    )

    private fun vector(v: Vector3) = listOf(v.x, v.y, v.z)
    private fun matrix(m: Matrix3) = (0 until 3).map { r -> (0 until 3).map { c -> m[r, c] } }

    /**
     * Parses a calibration file. Sections that are absent or null are not calibrated; quality
     * members may be missing (NaN, 0). Unknown members are ignored.
     * @throws DataFormatException naming [sourceName] and the member at fault.
     */
    @JvmStatic
    public fun parse(text: String, sourceName: String): Calibration = parse(Json.document(text, sourceName).rootObject())

    /** The calibration in [o]: a calibration file's root, or the member of a session's meta.json that holds one. */
    internal fun parse(o: JsonObject): Calibration {
        val r = Member(o)
        val root = r.o.map
        if (root["format"] != FORMAT) throw r.error("format", "expected \"$FORMAT\": not a calibration file")
        val version = r.number("format_version", Double.NaN)
        if (!(version >= 1.0) || version != Math.rint(version)) throw r.error("format_version", "missing or not a positive integer")
        if (version > FORMAT_VERSION) throw r.error("format_version", "${version.toLong()} is newer than this reader ($FORMAT_VERSION); update fusion")
        return Calibration(
            magnetometer = r.section("magnetometer")?.let { m ->
                MagnetometerCalibration(
                    m.correction("offset_uT", MAX_MAG_OFFSET_UT, "µT", "a hard iron beyond any phone magnetometer's range (±${MAX_MAG_OFFSET_UT.toInt()} µT)"), m.stream(SessionStream.MAGNETOMETER_UNCALIBRATED, SessionStream.MAGNETOMETER), m.model(), m.number("field_strength_uT", Double.NaN),
                    m.number("residual_rms_uT", Double.NaN), m.number("coverage", Double.NaN), m.number("samples", 0.0).toLong(),
                    m.number("magnitude_std_before_uT", Double.NaN), m.number("magnitude_std_after_uT", Double.NaN),
                )
            },
            gyroscope = r.section("gyroscope")?.let { g ->
                GyroscopeCalibration(
                    g.bias(), g.stream(SessionStream.GYROSCOPE_UNCALIBRATED, SessionStream.GYROSCOPE), g.number("still_time_s", Double.NaN), g.number("still_windows", 0.0).toInt(),
                    g.vector("bias_std_error_rad_s", required = false) ?: NAN3, g.vector("noise_std_rad_s", required = false) ?: NAN3,
                )
            },
            accelerometer = r.section("accelerometer")?.let { a ->
                AccelerometerCalibration(
                    a.correction("offset_m_s2", MAX_ACC_OFFSET_M_S2, "m/s²", "no phone accelerometer is that far off (offsets are well within ±$MAX_ACC_OFFSET_M_S2 m/s²; gravity is 9.81)"), a.stream(SessionStream.ACCELEROMETER), a.model(), a.number("gravity_m_s2", Double.NaN),
                    a.number("poses", 0.0).toInt(), a.number("residual_rms_m_s2", Double.NaN),
                )
            },
            refused = (root["refused"] as? Map<*, *>)?.entries?.associate { (k, v) -> k.toString() to v.toString() } ?: emptyMap(),
            source = root["source"] as? String ?: "",
            recording = root["recording"] as? String ?: "",
            device = root["device"] as? String ?: "",
        )
    }

    private val NAN3 = Vector3(Double.NaN, Double.NaN, Double.NaN)

    /** Largest hard-iron offset per axis a calibration may hold, µT: phones' magnetometers end at ±4900 µT. */
    internal const val MAX_MAG_OFFSET_UT: Double = 5000.0

    /** Largest gyroscope bias per axis, rad/s: phones' biases are hundredths of a rad/s; 1 rad/s is 57 °/s. */
    internal const val MAX_GYRO_BIAS_RAD_S: Double = 1.0

    /** Largest accelerometer offset per axis, m/s²: phones' zero-g offsets are tenths of a m/s². */
    internal const val MAX_ACC_OFFSET_M_S2: Double = 3.0

    /** One JSON object of the file, with errors naming its path and position. */
    private class Member(val o: JsonObject) {
        val map: Map<*, *> get() = o.map

        fun error(key: String, reason: String) = o.error(key, reason)

        fun section(key: String): Member? = o.objOrNull(key)?.let(::Member)

        fun number(key: String, default: Double): Double = o.double(key, default)

        fun vector(key: String, required: Boolean = true): Vector3? {
            if (map[key] == null) if (required) throw error(key, "missing") else return null
            return o.numbers(key, 3).let { Vector3(it[0], it[1], it[2]) }
        }

        /**
         * The offset [offsetKey] (each axis within ±[maxOffset] [unit], else [why]) and the matrix:
         * symmetric and positive definite, as every fit writes it (a rotation or a reflection would
         * turn the readings, not correct them).
         */
        fun correction(offsetKey: String, maxOffset: Double, unit: String, why: String): SensorCorrection {
            val rows = map["matrix"] as? List<*> ?: throw error("matrix", "expected an array of three rows of three numbers")
            if (rows.size != 3) throw error("matrix", "expected three rows, got ${rows.size}")
            val m = rows.indices.flatMap { i -> o.numbers("matrix", i, 3).toList() }
            val matrix = Matrix3.of(*m.toDoubleArray())
            val scale = m.maxOf { kotlin.math.abs(it) }
            if (!matrix.isFinite() || !matrix.isSymmetric(1e-6 * scale)) {
                throw error("matrix", "not a calibration matrix: not symmetric, as every fit's is (docs/CALIBRATION.md); it would turn the readings, not correct them")
            }
            if (!(matrix.determinant() > 0.0) || SymmetricEigen(matrix).values.any { !(it > 0.0) }) {
                throw error("matrix", "not a calibration matrix: not positive definite (it would flip or flatten the readings)")
            }
            val offset = vector(offsetKey)!!
            limit(offsetKey, offset, maxOffset, unit, why)
            return SensorCorrection(offset, matrix)
        }

        fun bias(): Vector3 = vector("bias_rad_s")!!.also {
            limit("bias_rad_s", it, MAX_GYRO_BIAS_RAD_S, "rad/s", "no phone gyroscope has such a bias (biases are hundredths of a rad/s)")
        }

        /** Fails naming [key] when an axis of [v] is beyond ±[max]: the calibration is wrong, not the recording. */
        private fun limit(key: String, v: Vector3, max: Double, unit: String, why: String) {
            val worst = listOf(v.x, v.y, v.z).maxOf { kotlin.math.abs(it) }
            if (!(worst <= max)) {
                val shown = if (worst.isFinite()) java.math.BigDecimal(worst).round(java.math.MathContext(4)).stripTrailingZeros().let { if (worst < 1e5) it.toPlainString() else it.toString() } else worst.toString()
                throw error(key, "$shown $unit: $why; this calibration is wrong for any recording")
            }
        }

        fun stream(vararg allowed: SessionStream): SessionStream {
            val key = map["stream"] as? String ?: throw error("stream", "missing (the stream it applies to)")
            val s = SessionStream.ofKey(key)
            if (s == null || s !in allowed) throw error("stream", "'$key' is not one of ${allowed.joinToString(", ") { it.key }}")
            return s
        }

        fun model(): EllipsoidModel {
            val name = map["model"] as? String ?: return EllipsoidModel.FULL
            return EllipsoidModel.entries.firstOrNull { it.name == name } ?: throw error("model", "unknown model '$name' (FULL, AXIS_ALIGNED or SPHERE)")
        }
    }
}
