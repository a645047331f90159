package dev.motionfusion.app.calibration

import android.content.Context
import android.text.format.DateUtils
import dev.motionfusion.app.R
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.Fit
import dev.motionfusion.core.calib.SensorCorrection
import java.util.Locale

/** The calibration screen's words and figures for a [CalibrationUiState]. */
internal object CalibrationText {
    fun instruction(c: Context, s: CalibrationUiState): String {
        s.unavailable?.let { return c.getString(R.string.calibration_unavailable, it) }
        return when (s.step) {
            CalibrationStep.MAGNETOMETER -> when (s.stage) {
                CalibrationStage.READY -> c.getString(R.string.calibration_mag_ready)
                CalibrationStage.COLLECTING -> c.getString(R.string.calibration_mag_collecting)
                CalibrationStage.RESULT -> resultHeadline(c, s)
            }
            CalibrationStep.POSES -> when (s.stage) {
                CalibrationStage.READY -> c.getString(R.string.calibration_poses_ready, s.minPoseS)
                CalibrationStage.COLLECTING -> s.askedFace?.let { c.getString(R.string.calibration_pose_asked, s.poseNumber, c.getString(PoseFacesView.faceName(it))) }
                    ?: c.getString(R.string.calibration_pose_all)
                CalibrationStage.RESULT -> resultHeadline(c, s)
            }
            CalibrationStep.STILL -> c.getString(R.string.calibration_still_ready) // the screen shows [still] instead
        }
    }

    private fun resultHeadline(c: Context, s: CalibrationUiState): String =
        c.getString(if (s.hasAccepted) R.string.calibration_result_ready else R.string.calibration_result_refused)

    fun progress(c: Context, s: CalibrationUiState): String = when {
        s.unavailable != null || s.stage == CalibrationStage.READY -> ""
        s.step == CalibrationStep.MAGNETOMETER ->
            c.getString(R.string.calibration_mag_progress, Math.round(100 * s.coverage).toInt(), Math.round(100 * s.minCoverage).toInt(), s.magSamples.toInt(), s.elapsedS)
        s.stage == CalibrationStage.RESULT -> c.getString(R.string.calibration_pose_done, s.poses, s.elapsedS)
        else -> c.getString(
            R.string.calibration_pose_progress, s.poses,
            if (s.still) c.getString(R.string.calibration_pose_still, s.holdS) else c.getString(R.string.calibration_pose_moving), s.elapsedS,
        )
    }

    /** The fitted values with their quality figures; refusals with their reasons. */
    fun result(c: Context, s: CalibrationUiState): String {
        if (s.stage != CalibrationStage.RESULT) return ""
        val lines = ArrayList<String>()
        when (s.step) {
            CalibrationStep.MAGNETOMETER -> when (val f = s.magFit) {
                is Fit.Done -> f.value.let { m ->
                    lines += "magnetometer (${m.stream.key}, ${m.model})"
                    lines += "hard iron  " + vec(m.correction.offset, "%.1f") + " µT"
                    if (m.model.name != "SPHERE") lines += rows("soft iron  ", m.correction)
                    lines += "field %.1f µT · residual %.2f µT".format(Locale.ROOT, m.fieldStrength, m.residualRms)
                    lines += "coverage %.0f %% · |B| spread %.1f → %.2f µT".format(Locale.ROOT, 100 * m.coverage, m.magnitudeStdBefore, m.magnitudeStdAfter)
                }
                is Fit.Refused -> lines += c.getString(R.string.calibration_refused, "magnetometer", f.reason)
                null -> Unit
            }
            CalibrationStep.STILL -> Unit
            CalibrationStep.POSES -> {
                when (val f = s.accFit) {
                    is Fit.Done -> f.value.let { a ->
                        lines += "accelerometer (${a.model}, ${a.poses} poses)"
                        lines += "offset  " + vec(a.correction.offset, "%.3f") + " m/s²"
                        lines += rows("scale   ", a.correction)
                        lines += "residual %.4f m/s² at g = %.5f m/s²".format(Locale.ROOT, a.residualRms, a.gravity)
                    }
                    is Fit.Refused -> lines += c.getString(R.string.calibration_refused, "accelerometer", f.reason)
                    null -> Unit
                }
                when (val f = s.gyroFit) {
                    is Fit.Done -> f.value.let { g ->
                        lines += "gyroscope bias (${g.stream.key})"
                        lines += "bias  " + vec(g.bias, "%.5f") + " rad/s"
                        lines += "±     " + vec(g.biasStdError, "%.5f") + " (standard error)"
                        lines += "noise " + vec(g.noiseStd, "%.4f") + " rad/s · still %.0f s".format(Locale.ROOT, g.stillTimeS)
                    }
                    is Fit.Refused -> lines += c.getString(R.string.calibration_refused, "gyroscope", f.reason)
                    null -> Unit
                }
            }
        }
        s.saveError?.let { lines += c.getString(R.string.calibration_save_failed, it) }
        return lines.joinToString("\n")
    }

    fun stored(c: Context, cal: Calibration?, usedLive: Boolean): String {
        val names = listOfNotNull(
            cal?.magnetometer?.let { "magnetometer" }, cal?.accelerometer?.let { "accelerometer" }, cal?.gyroscope?.let { "gyroscope" },
        )
        return when {
            names.isEmpty() -> c.getString(R.string.calibration_stored_none)
            usedLive -> c.getString(R.string.calibration_stored_applied, names.joinToString(", "))
            else -> c.getString(R.string.calibration_stored, names.joinToString(", "))
        }
    }

    /** The still-recording step's texts: instruction, progress and result lines. */
    data class Still(val instruction: String, val progress: String, val result: String, val fractionOfHour: Double, val recording: Boolean, val busy: Boolean)

    /** The still step for the recording state [rec] at [nowElapsedMs] (SystemClock.elapsedRealtime). */
    fun still(c: Context, rec: RecordingState, nowElapsedMs: Long): Still = when {
        rec is RecordingState.Active && rec.still -> {
            val s = rec.elapsedS(nowElapsedMs)
            Still(
                c.getString(R.string.calibration_still_recording),
                c.getString(R.string.calibration_still_progress, DateUtils.formatElapsedTime(s), rec.rows()) + "\n" + c.getString(R.string.calibration_still_needs),
                "", s / 3600.0, recording = true, busy = false,
            )
        }
        rec is RecordingState.Active || rec is RecordingState.Preparing ->
            Still(c.getString(R.string.calibration_still_busy), "", "", 0.0, recording = false, busy = true)
        rec is RecordingState.Ended && rec.still && rec.session != null ->
            Still(
                c.getString(R.string.calibration_still_ready), c.getString(R.string.calibration_still_needs),
                c.getString(R.string.calibration_still_ended, rec.session.name, rec.result.rows), 0.0, recording = false, busy = false,
            )
        else -> Still(
            c.getString(R.string.calibration_still_ready), c.getString(R.string.calibration_still_needs),
            if (rec is RecordingState.NotStarted) c.getString(R.string.record_not_started, rec.reason) else "", 0.0, recording = false, busy = false,
        )
    }

    private fun vec(v: Vector3, f: String) = listOf(v.x, v.y, v.z).joinToString(" ") { f.format(Locale.ROOT, it) }

    /** The correction's matrix after [label], a row a line, the rows aligned under the first. */
    private fun rows(label: String, c: SensorCorrection) = label + (0 until 3).joinToString("\n" + " ".repeat(label.length)) { r ->
        (0 until 3).joinToString(" ") { k -> "%6.3f".format(Locale.ROOT, c.matrix[r, k]) }
    }
}
