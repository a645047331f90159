/*
 * The IMU of the VIO data-set layouts (docs/IMPORT.md), as `fusion export` writes them and as
 * public data sets come:
 *   EuRoC (ASL)  a folder holding imu0/data.csv (usually mav0/), or that file alone:
 *                #timestamp [ns],w_RS_S_x [rad s^-1],…,a_RS_S_z [m s^-2]; a magnetometer in
 *                mag0/data.csv (#timestamp [ns],m_S_x [uT],…, as fusion export writes it) is read too
 *   Kalibr       imu0.csv (the input of kalibr_bagcreater): timestamp,omega_x,…,alpha_z
 * Times in integer ns; gyroscope rad/s, accelerometer m/s² (specific force), magnetometer µT, in
 * the IMU's own axes (for a phone's export, Android's device axes). Each row is one gyroscope and
 * one accelerometer reading at the same instant.
 */
package dev.motionfusion.core.input

import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.FileSet
import dev.motionfusion.core.event.SessionStream

internal object VioDatasetImport {
    private val EUROC_IMU = listOf("timestamp", "w_rs_s_x", "w_rs_s_y", "w_rs_s_z", "a_rs_s_x", "a_rs_s_y", "a_rs_s_z")
    private val EUROC_MAG = listOf("timestamp", "m_s_x", "m_s_y", "m_s_z")
    private val KALIBR_IMU = listOf("timestamp", "omega_x", "omega_y", "omega_z", "alpha_x", "alpha_y", "alpha_z")

    /** A header's names without EuRoC's leading '#' and the units in brackets, lower case. */
    private fun names(header: String): List<String> =
        ByteCsvReader.headerNames(header.trimStart().removePrefix("#")).map { it.substringBefore('[').trim().lowercase() }

    /** True when [header] is EuRoC's IMU header (columns in any order). */
    fun recognisesEuroc(header: String): Boolean = names(header).let { n -> EUROC_IMU.all { it in n } && n.size == n.toSet().size }

    /** True when [header] is Kalibr's imu0.csv header. */
    fun recognisesKalibr(header: String): Boolean = names(header).let { n -> KALIBR_IMU.all { it in n } && n.size == n.toSet().size }

    /** The EuRoC IMU file of the recording at [dir]: dir/imu0/data.csv, else the one file there with EuRoC's IMU header. */
    private fun eurocImu(files: FileSet, dir: String): String =
        files.find(dir, "imu0/data.csv")?.takeIf { p -> files.firstLine(p)?.let(::recognisesEuroc) == true }
            ?: files.filesIn(dir).first { p -> files.firstLine(p)?.let(::recognisesEuroc) == true }

    fun plan(files: FileSet, dir: String, format: RecordingFormat): ImportPlan {
        val imu = if (format == RecordingFormat.EUROC) eurocImu(files, dir) else files.filesIn(dir).first { p -> files.firstLine(p)?.let(::recognisesKalibr) == true }
        val header = names(files.firstLine(imu)!!)
        val columns = if (format == RecordingFormat.EUROC) EUROC_IMU else KALIBR_IMU
        fun at(k: Int) = header.indexOf(columns[k])
        val sources = ArrayList<StreamSource>()
        val time = at(0)
        // Accelerometer before gyroscope at the same instant (the merge's order of streams): each gyroscope step holds its row's accelerometer.
        sources += source(SessionStream.GYROSCOPE, imu, time, IntArray(3) { at(1 + it) })
        sources += source(SessionStream.ACCELEROMETER, imu, time, IntArray(3) { at(4 + it) })
        val notes = ArrayList<String>()
        if (format == RecordingFormat.EUROC) {
            val base = if (imu.endsWith("imu0/data.csv", ignoreCase = true)) imu.removeRange(imu.length - "imu0/data.csv".length, imu.length) else null
            val mag = base?.let { files.find(it, "mag0/data.csv") }
            val magHeader = mag?.let { files.firstLine(it) }?.let(::names)
            if (mag != null && magHeader != null && EUROC_MAG.all { it in magHeader }) {
                sources += source(SessionStream.MAGNETOMETER, mag, magHeader.indexOf("timestamp"), IntArray(3) { magHeader.indexOf(EUROC_MAG[1 + it]) })
            } else if (mag != null) {
                notes += "${files.displayName(mag)} left out: its header is not #timestamp [ns],m_S_x [uT],m_S_y [uT],m_S_z [uT]"
            }
        }
        return ImportPlan(sources, notes)
    }

    private fun source(stream: SessionStream, path: String, time: Int, values: IntArray): StreamSource {
        val map = ColumnMap(stream, path, Dialect.COMMA, time, true, values, DoubleArray(3) { 1.0 })
        return StreamSource(stream) { f -> map.open(f) }
    }
}
