package dev.motionfusion.app.calibration

import android.content.Context
import android.text.format.DateUtils
import dev.motionfusion.app.R
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.ui.Formats
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.EllipsoidModel
import dev.motionfusion.core.calib.Fit
import dev.motionfusion.core.calib.RefusalKind
import dev.motionfusion.core.calib.SensorCorrection
import dev.motionfusion.core.event.SessionStream
import java.util.Locale

/** The calibration screen's words and figures for a [CalibrationUiState]. */
internal object CalibrationText {
    fun instruction(c: Context, s: CalibrationUiState): String {
        s.unavailable?.let { return c.getString(R.string.calibration_unavailable, c.getString(it)) }
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

    /** Which readings a fit used, in words: the phone's calibrated stream or the uncalibrated one. */
    private fun source(c: Context, stream: SessionStream): String = c.getString(
        if (stream == SessionStream.MAGNETOMETER_UNCALIBRATED || stream == SessionStream.GYROSCOPE_UNCALIBRATED) R.string.calibration_source_raw
        else R.string.calibration_source_phone,
    )

    /** What a fit corrects, in words. */
    private fun model(c: Context, m: EllipsoidModel): String = c.getString(
        when (m) {
            EllipsoidModel.FULL -> R.string.calibration_model_full
            EllipsoidModel.AXIS_ALIGNED -> R.string.calibration_model_axis_aligned
            EllipsoidModel.SPHERE -> R.string.calibration_model_sphere
        },
    )

    /** The fitted values with their quality figures; refusals with their reasons (fusion-core's words, as the detail). */
    fun result(c: Context, s: CalibrationUiState): String {
        if (s.stage != CalibrationStage.RESULT) return ""
        val l = Formats.locale(c)
        val lines = ArrayList<String>()
        when (s.step) {
            CalibrationStep.MAGNETOMETER -> when (val f = s.magFit) {
                is Fit.Done -> f.value.let { m ->
                    lines += c.getString(R.string.calibration_result_mag, source(c, m.stream), model(c, m.model))
                    lines += c.getString(R.string.calibration_result_hard_iron, vec(l, m.correction.offset, "%.1f"))
                    if (m.model != EllipsoidModel.SPHERE) lines += rows(l, c.getString(R.string.calibration_result_soft_iron), m.correction)
                    lines += c.getString(R.string.calibration_result_field, m.fieldStrength, m.residualRms)
                    lines += c.getString(R.string.calibration_result_coverage, 100 * m.coverage, m.magnitudeStdBefore, m.magnitudeStdAfter)
                }
                is Fit.Refused -> lines += c.getString(R.string.calibration_refused, c.getString(R.string.kind_magnetometer), refusal(c, f))
                null -> Unit
            }
            CalibrationStep.STILL -> Unit
            CalibrationStep.POSES -> {
                when (val f = s.accFit) {
                    is Fit.Done -> f.value.let { a ->
                        lines += c.resources.getQuantityString(R.plurals.calibration_result_acc, a.poses, model(c, a.model), a.poses)
                        lines += c.getString(R.string.calibration_result_offset, vec(l, a.correction.offset, "%.3f"))
                        lines += rows(l, c.getString(R.string.calibration_result_scale), a.correction)
                        lines += c.getString(R.string.calibration_result_acc_residual, a.residualRms, a.gravity)
                    }
                    is Fit.Refused -> lines += c.getString(R.string.calibration_refused, c.getString(R.string.kind_accelerometer), refusal(c, f))
                    null -> Unit
                }
                when (val f = s.gyroFit) {
                    is Fit.Done -> f.value.let { g ->
                        lines += c.getString(R.string.calibration_result_gyro, source(c, g.stream))
                        lines += c.getString(R.string.calibration_result_bias, vec(l, g.bias, "%.5f"))
                        lines += c.getString(R.string.calibration_result_bias_error, vec(l, g.biasStdError, "%.5f"))
                        lines += c.getString(R.string.calibration_result_noise, vec(l, g.noiseStd, "%.4f"), g.stillTimeS)
                    }
                    is Fit.Refused -> lines += c.getString(R.string.calibration_refused, c.getString(R.string.kind_gyroscope), refusal(c, f))
                    null -> Unit
                }
            }
        }
        s.saveError?.let { lines += c.getString(R.string.calibration_save_failed, it) }
        return lines.joinToString("\n")
    }

    /** Why a fit was refused, in the resources' words with fusion-core's figures; a reason of another kind as fusion-core says it. */
    fun refusal(c: Context, f: Fit.Refused): String {
        val n = f.figures
        fun axis() = c.getString(
            when (n[0].toInt()) {
                0 -> R.string.calibration_axis_x
                1 -> R.string.calibration_axis_y
                else -> R.string.calibration_axis_z
            },
        )
        return when (f.kind) {
            RefusalKind.FEW_SAMPLES -> c.getString(R.string.calibration_refusal_few_samples, n[0].toInt())
            RefusalKind.NO_ELLIPSOID -> c.getString(R.string.calibration_refusal_no_ellipsoid)
            RefusalKind.FIELD_OUT_OF_RANGE -> c.getString(R.string.calibration_refusal_field_out_of_range, n[0], n[1], n[2])
            RefusalKind.FEW_DIRECTIONS -> c.getString(R.string.calibration_refusal_few_directions, n[0], n[1])
            RefusalKind.DISTURBED -> c.getString(R.string.calibration_refusal_disturbed, n[0], n[1], n[2])
            RefusalKind.NOT_STILL -> c.getString(R.string.calibration_refusal_not_still, n[0], n[1])
            RefusalKind.FEW_POSES -> c.resources.getQuantityString(R.plurals.calibration_refusal_few_poses, n[0].toInt(), n[0].toInt(), n[1])
            RefusalKind.AXIS_NEVER_UP -> c.getString(R.string.calibration_refusal_axis_up, axis(), n[1])
            RefusalKind.AXIS_NEVER_DOWN -> c.getString(R.string.calibration_refusal_axis_down, axis(), n[1])
            RefusalKind.POSES_NO_ELLIPSOID -> c.getString(R.string.calibration_refusal_poses_no_ellipsoid)
            RefusalKind.OTHER -> f.reason
        }
    }

    fun stored(c: Context, cal: Calibration?, usedLive: Boolean): String {
        val names = listOfNotNull(
            cal?.magnetometer?.let { R.string.stream_magnetometer }, cal?.accelerometer?.let { R.string.stream_accelerometer }, cal?.gyroscope?.let { R.string.stream_gyroscope },
        ).map { c.getString(it) }
        val list = names.joinToString(c.getString(R.string.list_separator))
        return when {
            names.isEmpty() -> c.getString(R.string.calibration_stored_none)
            usedLive -> c.getString(R.string.calibration_stored_applied, list)
            else -> c.getString(R.string.calibration_stored, list)
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
            if (rec is RecordingState.NotStarted) rec.text(c) else "", 0.0, recording = false, busy = false,
        )
    }

    private fun vec(l: Locale, v: Vector3, f: String) = listOf(v.x, v.y, v.z).joinToString(" ") { f.format(l, it) }

    /** The correction's matrix after [label], a row a line, the rows aligned under the first. */
    private fun rows(l: Locale, label: String, c: SensorCorrection): String {
        val head = "$label  "
        return head + (0 until 3).joinToString("\n" + " ".repeat(head.length)) { r ->
            (0 until 3).joinToString(" ") { k -> "%6.3f".format(l, c.matrix[r, k]) }
        }
    }
}
