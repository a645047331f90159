package dev.motionfusion.app.export

import androidx.annotation.StringRes
import dev.motionfusion.app.R
import dev.motionfusion.core.export.ExportFormat

/**
 * What a session leaves the app as: the project's own zip, or one of fusion-core's export formats
 * ([ExportFormat], the files `fusion export` writes; a folder format zipped), or the noise
 * configurations of a still recording (`fusion allan --configs`, zipped). [mime] and the file name's
 * [suffix] as Share and Save as give them.
 */
internal enum class ExportKind(val format: ExportFormat?, val mime: String, val suffix: String, @StringRes val label: Int) {
    SESSION(null, ExportProvider.MIME_ZIP, ".zip", R.string.export_format_session),
    EUROC(ExportFormat.EUROC, ExportProvider.MIME_ZIP, "-euroc.zip", R.string.export_format_euroc),
    KALIBR(ExportFormat.KALIBR, ExportProvider.MIME_ZIP, "-kalibr.zip", R.string.export_format_kalibr),
    ROS2(ExportFormat.ROS2, ExportProvider.MIME_BINARY, ".mcap", R.string.export_format_ros2),
    GCSV(ExportFormat.GCSV, ExportProvider.MIME_TEXT, ".gcsv", R.string.export_format_gcsv),

    /** Only for a still recording: kalibr imu.yaml, OpenVINS, VINS, ORB-SLAM3. */
    NOISE(null, ExportProvider.MIME_ZIP, "-noise.zip", R.string.export_format_noise),
    ;

    /** The format holds the fused orientation, so a heading tare changes it. */
    val hasOrientation: Boolean get() = this == EUROC || this == ROS2

    fun fileName(session: String): String = session + suffix
}

/** The choice on the detail screen: the [kind], and the heading zeroed at the filter's first orientation ([zeroHeading], orientation formats only). */
internal data class ExportChoice(val kind: ExportKind = ExportKind.SESSION, val zeroHeading: Boolean = false)
